#include "parallel/shared_forward.hpp"

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>
#include <sched.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "parallel/gathering.hpp"
#include "parallel/ghosts.hpp"

namespace granule::parallel {

namespace {
// A spinning core's hint to the processor (and to its other hyperthread).
inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}
}  // namespace

template <int D>
SharedForward<D>::SharedForward(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  const char* setting = std::getenv("GRANULE_MPI_SHARED");
  const bool wanted = !(setting && std::string(setting) == "0");
  MPI_Comm node;
  check_mpi(MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
            "MPI_Comm_split_type");
  int node_size = 0;
  MPI_Comm_size(node, &node_size);
  MPI_Comm_free(&node);
  // Every rank must take the same way: used only where all can.
  const int here = wanted && node_size == size_ ? 1 : 0;
  int everywhere = 0;
  MPI_Allreduce(&here, &everywhere, 1, MPI_INT, MPI_MIN, comm_);
  usable_ = everywhere == 1 && size_ > 1;
  part_.assign(static_cast<std::size_t>(size_), nullptr);
  halves_.assign(static_cast<std::size_t>(size_), 0);
}

template <int D>
SharedForward<D>::~SharedForward() {
  if (window_ == MPI_WIN_NULL) return;
  MPI_Win_unlock_all(window_);
  MPI_Win_free(&window_);
}

template <int D>
std::size_t SharedForward<D>::needed(const GhostPlan& plan, int count) const {
  constexpr std::size_t per = ghost_state_doubles<D>;
  std::size_t doubles = 2 * static_cast<std::size_t>(size_) + static_cast<std::size_t>(count);
  for (const auto& to_rank : plan.send) doubles += to_rank.size() * per;
  return doubles;
}

template <int D>
void SharedForward<D>::allocate(std::size_t half) {
  if (window_ != MPI_WIN_NULL) {
    MPI_Win_unlock_all(window_);
    MPI_Win_free(&window_);
  }
  MPI_Info info;
  MPI_Info_create(&info);
  MPI_Info_set(info, "alloc_shared_noncontig", "true");  // each part near its own core
  double* base = nullptr;
  const int code =
      MPI_Win_allocate_shared(static_cast<MPI_Aint>((flag_doubles + 2 * half) * sizeof(double)),
                              sizeof(double), info, comm_, &base, &window_);
  MPI_Info_free(&info);
  check_mpi(code, "MPI_Win_allocate_shared");
  check_mpi(MPI_Win_lock_all(MPI_MODE_NOCHECK, window_), "MPI_Win_lock_all");
  for (int k = 0; k < size_; ++k) {
    MPI_Aint bytes = 0;
    int unit = 0;
    double* at = nullptr;
    check_mpi(MPI_Win_shared_query(window_, k, &bytes, &unit, &at), "MPI_Win_shared_query");
    part_[static_cast<std::size_t>(k)] = at + flag_doubles;
    halves_[static_cast<std::size_t>(k)] =
        (static_cast<std::size_t>(bytes) / sizeof(double) - flag_doubles) / 2;
  }
  turn_ = 0;
  // The ranks meet by their flags where the window's memory is the processes'
  // own (the unified model); else by MPI_Barrier with MPI_Win_sync around it.
  int* model = nullptr;
  int found = 0;
  MPI_Win_get_attr(window_, MPI_WIN_MODEL, &model, &found);
  by_flags_ = found && model && *model == MPI_WIN_UNIFIED;
  // Each flag holds the forwards made so far (the same on every rank), set
  // before any rank reads it.
  __atomic_store_n(flag(static_cast<std::size_t>(rank_)), rounds_, __ATOMIC_RELEASE);
  MPI_Win_sync(window_);
  check_mpi(MPI_Barrier(comm_), "MPI_Barrier");
  MPI_Win_sync(window_);
}

template <int D>
void SharedForward<D>::meet() {
  if (!by_flags_) {
    // Written, then everyone's visible: the sync-barrier-sync of MPI's
    // separate memory model for shared windows.
    MPI_Win_sync(window_);
    check_mpi(MPI_Barrier(comm_), "MPI_Barrier");
    MPI_Win_sync(window_);
    return;
  }
  // This rank's writes before its flag (release); each other rank's before
  // its flag was seen (acquire): the barrier of the two halves' argument.
  ++rounds_;
  __atomic_store_n(flag(static_cast<std::size_t>(rank_)), rounds_, __ATOMIC_RELEASE);
  for (std::size_t k = 0; k < part_.size(); ++k) {
    if (static_cast<int>(k) == rank_) continue;
    // Pausing while the other rank computes; after a while yielding the core,
    // so that ranks sharing cores (mpirun --oversubscribe) let it run.
    for (int spins = 0; __atomic_load_n(flag(k), __ATOMIC_ACQUIRE) < rounds_; ++spins) {
      if (spins < spins_before_yield)
        pause();
      else
        sched_yield();
    }
  }
}

template <int D>
void SharedForward<D>::fit(const GhostPlan& plan, int count) {
  const std::size_t need = needed(plan, count);
  const int mine = need > own_half() ? 1 : 0;
  int any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm_);
  // Room to grow, so that a drifting ghost count does not re-make it often.
  if (any) allocate(std::max(need + need / 2, own_half()));
}

template <int D>
void SharedForward<D>::forward(const Decomposition<D>& d, const GhostPlan& plan,
                               const std::vector<ParticleRecord<D>>& owned,
                               std::vector<ParticleRecord<D>>& ghosts, double* maxima, int count) {
  constexpr std::size_t per = ghost_state_doubles<D>;
  const std::size_t ranks = static_cast<std::size_t>(size_);
  const std::size_t extra = maxima ? static_cast<std::size_t>(count) : 0;
  if (needed(plan, static_cast<int>(extra)) > own_half())
    throw std::runtime_error("parallel: the shared ghost window was not fitted to the plan");
  const auto shifts = periodic_shifts(d);
  // This rank's half: each destination's block (offset, length), the maxima, the blocks.
  double* const mine = part_[static_cast<std::size_t>(rank_)] + turn_ * own_half();
  std::size_t at = 2 * ranks + extra;
  for (std::size_t e = 0; e < extra; ++e) mine[2 * ranks + e] = maxima[e];
  for (std::size_t k = 0; k < ranks; ++k) {
    mine[2 * k] = static_cast<double>(at);
    mine[2 * k + 1] = static_cast<double>(plan.send[k].size() * per);
    double* end = mine + at;
    for (const auto& s : plan.send[k])
      end = put_ghost_state(end, owned[s.index], shifts[static_cast<std::size_t>(s.image)]);
    at = static_cast<std::size_t>(end - mine);
  }
  meet();
  for (std::size_t k = 0; k < ranks; ++k) {
    const double* const theirs = part_[k] + turn_ * halves_[k];
    for (std::size_t e = 0; e < extra; ++e) maxima[e] = std::max(maxima[e], theirs[2 * ranks + e]);
    const std::size_t from = static_cast<std::size_t>(theirs[2 * rank_]);
    const std::size_t length = static_cast<std::size_t>(theirs[2 * rank_ + 1]);
    if (length != plan.place[k].size() * per || from + length > halves_[k])
      throw std::runtime_error(
          fmt::format("parallel: rank {} shares {} values for rank {}, which expects {}", k, length,
                      rank_, plan.place[k].size() * per));
    const double* q = theirs + from;
    for (const std::size_t g : plan.place[k]) q = take_ghost_state(q, ghosts[g]);
  }
  turn_ ^= 1;
}

template class SharedForward<2>;
template class SharedForward<3>;

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
