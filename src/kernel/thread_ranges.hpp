// The pair kernel's threads: each takes a contiguous range of a bucket's
// candidates. A particle that only one range reaches gets its forces added by
// that thread as they come, in slot order; one that several ranges reach (a
// thin layer where the ranges meet, in space-filling-curve order) gets all of
// them deferred and added after the others, still in slot order. Either way
// the sum is the single thread's, bit for bit, wherever the ranges meet: they
// are moved (rebalance) when the work gathers in one of them.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace granule {

// What each thread of a pair loop did since its range was last judged
// (ThreadRanges::rebalance), and the cost of a listed contact in candidates,
// fitted to those times.
struct ThreadPace {
  std::vector<double> seconds, candidates, listed;  // per thread
  std::int64_t steps = 0;
  bool moved = false;  // the ranges moved since the lists were first built (else judged at once)
  double contact_weight = 12;
  void reset(int team) {
    seconds.assign(team, 0.0), candidates.assign(team, 0.0), listed.assign(team, 0.0);
    steps = 0;
  }
};

template <int D>
class ThreadRanges {
 public:
  // A force and torque onto a particle two ranges share, kept for later.
  struct Deferred {
    std::uint32_t particle;
    Vec<D> force;
    Spin<D> torque;
  };

  // Where the threads' candidate ranges start (and the last ends).
  std::vector<std::int64_t> split;
  // 1 for each particle that two ranges name (its forces are summed after the others').
  std::vector<std::uint8_t> shared;
  // Where each thread's particles start for adding the deferred forces (and
  // the last end): cut so that each gets as many shared particles.
  std::vector<std::uint32_t> shared_split;
  // Per thread, this step's deferred contributions in its range's order.
  std::vector<std::vector<Deferred>> deferred;
  ThreadPace pace;   // what rebalance() judges the ranges by; kept over list rebuilds
  int ran_team = 0;  // the threads OpenMP gave the last step's loop

  // Before a step on `team` threads over `count` candidates naming `n`
  // particles (pairs i, j): the ranges carried over from the last lists with
  // their timings (on_new_list), else equal ones. Returns the seconds spent
  // marking shared particles.
  double prepare(int team, std::int64_t count, std::size_t n, const std::uint32_t* i,
                 const std::uint32_t* j) {
    double seconds = 0;
    if (split.size() != static_cast<std::size_t>(team) + 1 || shared.size() != n) {
      const bool carried = split.size() == static_cast<std::size_t>(team) + 1 &&
                           split.front() == 0 && split.back() == count &&
                           pace.seconds.size() == static_cast<std::size_t>(team);
      if (carried) {
        seconds += mark_shared(count, n, i, j);
      } else {
        std::vector<std::int64_t> equal(team + 1);
        for (int t = 0; t <= team; ++t) equal[t] = count * t / team;
        seconds += set_split(std::move(equal), count, n, i, j);
        pace.moved = false;
      }
    }
    if (deferred.size() < static_cast<std::size_t>(team)) deferred.resize(team);
    return seconds;
  }

  // A new candidate list of `fresh` entries replacing one of `old`: the
  // ranges keep their shares of the candidates, and what rebalance() has
  // measured of them so far (in a flow the lists are rebuilt every few
  // steps); the shared particles are marked afresh at the next step.
  void on_new_list(std::size_t old, std::size_t fresh) {
    first_named_.clear(), last_named_.clear(), shared.clear();
    if (split.size() > 1 && old > 0) {
      for (auto& cut : split)
        cut = static_cast<std::int64_t>(static_cast<double>(cut) / static_cast<double>(old) *
                                        static_cast<double>(fresh));
      split.front() = 0, split.back() = static_cast<std::int64_t>(fresh);
    } else {
      split.clear();
    }
  }

  // Moves the ranges when one thread is busier than the others: a pile in one
  // part of the candidates, or a thread the host slows down (the cores are
  // shared). The work is modelled as one unit per candidate (the listing pass)
  // and `contact_weight` units per listed contact, the weight fitted to the
  // threads' measured times (it depends on the model and the machine: ~11 for
  // the linear law on this project's machine). Each thread's pace, units per
  // second over the steps judged, sets its share: the new cut points share
  // this step's candidates and listed contacts out in proportion (so a range
  // whose units cost more, or a slower thread, gets fewer). Judged every 16
  // steps, acting on a spread of more than 3 % between the busiest thread and
  // the mean: moving the ranges costs a pass over the particles (mark_shared).
  // The forces do not depend on where the ranges meet, so neither do the
  // results. `lists` are the threads' lists of this step (entries k << 1 | bit,
  // increasing k). Returns whether the ranges moved; adds the marking time to
  // `seconds`.
  template <typename Lists>
  bool rebalance(int team, std::int64_t count, std::size_t n, const std::uint32_t* i,
                 const std::uint32_t* j, const Lists& lists, double& seconds) {
    constexpr std::int64_t min_interval = 16;
    ++pace.steps;
    if (pace.moved && pace.steps < min_interval) return false;
    double most = 0, sum = 0;
    for (int t = 0; t < team; ++t) {
      most = std::max(most, pace.seconds[t]);
      sum += pace.seconds[t];
    }
    if (!(most * team > 1.03 * sum)) {
      if (pace.steps >= 4 * min_interval) pace.reset(team);  // judge recent steps
      return false;
    }
    // Least squares for time = a candidates + c listed over the threads; the
    // weight c / a, blended with the last one, when the threads' mixes differ.
    double cc = 0, cl = 0, ll = 0, ct = 0, lt = 0;
    for (int t = 0; t < team; ++t) {
      const double c = pace.candidates[t], l = pace.listed[t], time = pace.seconds[t];
      cc += c * c, cl += c * l, ll += l * l, ct += c * time, lt += l * time;
    }
    const double det = cc * ll - cl * cl;
    if (det > 1e-3 * cc * ll) {
      const double a = (ct * ll - lt * cl) / det, c = (lt * cc - ct * cl) / det;
      if (a > 0 && c > 0)
        pace.contact_weight = std::clamp(0.5 * (pace.contact_weight + c / a), 1.0, 200.0);
    }
    // Walk the candidates with the listed ones (in increasing k across the
    // lists) and cut where the cumulative cost reaches each thread's share.
    std::int64_t listed = 0;
    for (const auto& list : lists) listed += static_cast<std::int64_t>(list.count);
    const double weight = pace.contact_weight;
    const double total = static_cast<double>(count) + weight * static_cast<double>(listed);
    // The threads' paces, and where each cut falls as a fraction of the total.
    std::vector<double> share(team + 1, 0.0);
    bool paced = true;
    for (int t = 0; t < team; ++t) {
      const double units = pace.candidates[t] + weight * pace.listed[t];
      share[t + 1] = pace.seconds[t] > 0 ? units / pace.seconds[t] : 0;
      paced = paced && share[t + 1] > 0 && std::isfinite(share[t + 1]);
    }
    for (int t = 1; t <= team; ++t) share[t] = paced ? share[t - 1] + share[t] : t;
    std::vector<std::int64_t> cuts(team + 1, count);
    cuts[0] = 0;
    int next = 1;
    std::int64_t listed_before = 0;
    auto cut_until = [&](std::int64_t k) {  // cuts that fall at or before candidate k
      while (next < team && static_cast<double>(k) + weight * static_cast<double>(listed_before) >=
                                total * share[next] / share[team])
        cuts[next++] = k;
    };
    for (const auto& list : lists)
      for (const std::uint32_t entry : list) {
        cut_until(entry >> 1);
        ++listed_before;
      }
    cut_until(count);
    seconds += set_split(std::move(cuts), count, n, i, j);
    pace.moved = true;
    return true;
  }

 private:
  using Clock = std::chrono::steady_clock;
  // The first and the last candidate that names each particle (none: ~0u
  // and 0), found once per list: a particle is shared when they fall in two
  // ranges, so moving the ranges costs a pass over the particles.
  std::vector<std::uint32_t> first_named_, last_named_;

  // New ranges: which particles they share, and fresh timings.
  double set_split(std::vector<std::int64_t> cuts, std::int64_t count, std::size_t n,
                   const std::uint32_t* i, const std::uint32_t* j) {
    split = std::move(cuts);
    const double seconds = mark_shared(count, n, i, j);
    pace.reset(static_cast<int>(split.size()) - 1);
    return seconds;
  }

  // Which particles the ranges share: those some candidate of two ranges
  // names, that is, whose first and last naming candidates lie in two ranges
  // (they are contiguous). Timed as part of the fixed-order sums
  // (sim:timings().scatter).
  double mark_shared(std::int64_t count, std::size_t n, const std::uint32_t* i,
                     const std::uint32_t* j) {
    const auto start = Clock::now();
    constexpr std::uint32_t none = ~0u;
    if (first_named_.size() != n) {  // once per list
      first_named_.assign(n, none);
      last_named_.assign(n, 0);
      for (std::int64_t k = 0; k < count; ++k)
        for (const std::uint32_t p : {i[k], j[k]}) {
          if (first_named_[p] == none) first_named_[p] = static_cast<std::uint32_t>(k);
          last_named_[p] = static_cast<std::uint32_t>(k);
        }
    }
    const int team = static_cast<int>(split.size()) - 1;
    shared.assign(n, 0);
    std::size_t shared_count = 0;
    for (std::size_t p = 0; p < n; ++p) {
      const std::uint32_t first = first_named_[p], last = last_named_[p];
      if (first == none) continue;
      // A cut between them (split[r] is where range r starts).
      for (int r = 1; r < team; ++r)
        if (static_cast<std::int64_t>(first) < split[r] &&
            split[r] <= static_cast<std::int64_t>(last)) {
          shared[p] = 1;
          ++shared_count;
          break;
        }
    }
    // The deferred forces are added thread by thread, each to its own
    // particles: cut those so that each thread gets its share of the shared
    // ones (they lie around where the ranges meet, not where the particles'
    // halves do).
    shared_split.assign(team + 1, static_cast<std::uint32_t>(n));
    shared_split[0] = 0;
    std::size_t seen = 0;
    int next = 1;
    for (std::size_t p = 0; p < n && next < team; ++p) {
      while (next < team && seen >= shared_count * next / team)
        shared_split[next++] = static_cast<std::uint32_t>(p);
      seen += shared[p];
    }
    return std::chrono::duration<double>(Clock::now() - start).count();
  }
};

}  // namespace granule
