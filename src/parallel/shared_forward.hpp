// The ghost forward between ranks of one machine through memory they share
// (an MPI-3 shared window): each rank writes the states it sends into its own
// part of the window, the ranks meet, and each copies what it needs straight
// from its senders' parts. On a small scene a step's messages cost a sizeable
// part of the step (docs/parallel.md); this is one meeting of the ranks (by
// flags in the window: meet()) and two copies. The same doubles arrive as
// forward_ghosts (exchange.hpp) would bring them, so the results are the same
// bits.
//
// Each rank's part has two halves, used on alternate steps: a rank that has
// passed step s's meeting writes the other half, while a slower rank may
// still be reading step s's; it can reach that half again only through step
// s + 1's meeting, which the slower one enters after its reads.
#pragma once

#ifdef GRANULE_HAVE_MPI

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "parallel/exchange.hpp"

namespace granule::parallel {

template <int D>
class SharedForward {
 public:
  // Collective over `comm`. Usable when every rank of `comm` is on this
  // machine and GRANULE_MPI_SHARED is not 0 (the messages' way, for tests
  // and for comparison).
  explicit SharedForward(MPI_Comm comm);
  ~SharedForward();  // collective (MPI_Win_free)
  SharedForward(const SharedForward&) = delete;
  SharedForward& operator=(const SharedForward&) = delete;

  bool usable() const { return usable_; }
  // After each new ghost plan (collective): the window made large enough for
  // what this rank sends and `count` maxima.
  void fit(const GhostPlan& plan, int count);
  // As forward_ghosts: the ghosts' states from their owners, and with
  // `maxima` each value's maximum over the ranks (every rank's `count`).
  void forward(const Decomposition<D>& d, const GhostPlan& plan,
               const std::vector<ParticleRecord<D>>& owned, std::vector<ParticleRecord<D>>& ghosts,
               double* maxima, int count);

 private:
  // Doubles in one half of a rank's part: for each rank its block's offset
  // and length, the maxima, then the blocks.
  std::size_t needed(const GhostPlan& plan, int count) const;
  void allocate(std::size_t half);  // collective
  // The step's meeting of the ranks, after each has written its half: by
  // their flags, or by MPI_Barrier (by_flags_).
  void meet();
  std::size_t own_half() const { return halves_[static_cast<std::size_t>(rank_)]; }
  // Rank k's flag: the cache line ahead of its halves.
  std::uint64_t* flag(std::size_t k) const {
    return reinterpret_cast<std::uint64_t*>(part_[k] - flag_doubles);
  }

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  bool usable_ = false;
  MPI_Win window_ = MPI_WIN_NULL;
  // Each rank's part starts with a cache line holding its flag (the count of
  // forwards it has written), then its two halves.
  static constexpr std::size_t flag_doubles = 8;
  // Pauses before a waiting rank starts yielding its core (~0.1 ms).
  static constexpr int spins_before_yield = 2000;
  std::vector<double*> part_;        // each rank's halves, as this process sees them
  std::vector<std::size_t> halves_;  // each rank's half size
  int turn_ = 0;                     // the half this step writes
  std::uint64_t rounds_ = 0;         // forwards made
  bool by_flags_ = false;
};

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
