// How many threads each loop of a step runs on, decided in one place, and the
// two ways a loop runs on them. The results never depend on it: every loop
// sums in slot (or particle) order whatever the team (docs/architecture.md).
#pragma once

#include <cstdint>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace granule {

struct ThreadPolicy {
  int threads = 1;  // what the user allows (SimulationBase::thread_count())
  // Below these sizes a loop runs on one thread: a parallel region costs
  // microseconds, more than a small scene's whole loop.
  std::int64_t min_candidates = 32768, min_particles = 16384;

  // The step adds contact forces (and the walls' reactions) directly, on one
  // thread, when it has one thread or too few candidates for a team.
  bool fused(std::int64_t slots) const { return threads == 1 || slots < min_candidates; }
  // A pair kernel's team for a bucket of `candidates`.
  int pair_team(std::int64_t candidates) const {
    return candidates >= min_candidates ? threads : 1;
  }
  // Wall contacts cost more per candidate than pairs (each one reaches a
  // particle's data on its own), so they go parallel from a smaller list.
  int wall_team(std::int64_t candidates, bool fused_step) const {
    return !fused_step && candidates >= min_candidates / 8 ? threads : 1;
  }
  // Loops over particles (zeroing forces, integration).
  bool particles_parallel(std::int64_t particles) const {
    return threads > 1 && particles >= min_particles;
  }
};

// Runs a contact kernel's work(t, nt, touching, max_ratio) on a team of
// threads (an OpenMP region) or, for a team of one, directly: summing the
// contact counts and taking the largest overlap ratio.
template <typename Work>
void run_on_team(int team, Work& work, std::int64_t& touching_out, double& max_ratio_out) {
  std::int64_t touching = 0;
  double max_ratio = 0;
  if (team > 1) {
#pragma omp parallel num_threads(team) reduction(+ : touching) reduction(max : max_ratio)
    work(omp_get_thread_num(), omp_get_num_threads(), touching, max_ratio);
  } else {
    work(0, 1, touching, max_ratio);
  }
  touching_out += touching;
  if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
}

// Runs range(lo, hi) over the particles [0, n): split among a team of threads
// (an OpenMP region, each thread a contiguous part) when `parallel`, else once.
template <typename Range>
void over_particles(bool parallel, int threads, std::int64_t n, Range&& range) {
  if (!parallel) return range(std::int64_t{0}, n);
#pragma omp parallel num_threads(threads)
  {
    const std::int64_t t = omp_get_thread_num(), nt = omp_get_num_threads();
    range(n * t / nt, n * (t + 1) / nt);
  }
}

}  // namespace granule
