// What the distributed run's ranks gather from one another: every rank's
// bytes on every rank, read back with a check, and the step's tallies summed
// over the ranks (DistributedRun::tallies). Internal to src/parallel.
#pragma once

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/bytes.hpp"
#include "core/errors.hpp"

namespace granule::parallel {

// An MPI call's code: an error names the call and MPI's reason.
inline void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw std::runtime_error(fmt::format("parallel: {} failed: {}", what, std::string(text, length)));
}

// A value of a gathered record (a clear error past its end).
template <typename T>
T take_gathered(const std::string& in, std::size_t& at) {
  return bytes::take<T>(in, at, "distributed run: a gathered record");
}

// The step's tallies over the ranks (DistributedRun::tallies).
struct Tallies {
  std::int64_t particles = 0, pair_contacts = 0, pair_batched = 0, wall_contacts = 0,
               wall_batched = 0;
  double max_overlap_ratio = 0;
};

// One rank's tallies, read from `all` at `at`, added to `sum`.
inline void add_tallies(Tallies& sum, const std::string& all, std::size_t& at) {
  sum.particles += take_gathered<std::int64_t>(all, at);
  sum.pair_contacts += take_gathered<std::int64_t>(all, at);
  sum.pair_batched += take_gathered<std::int64_t>(all, at);
  sum.wall_contacts += take_gathered<std::int64_t>(all, at);
  sum.wall_batched += take_gathered<std::int64_t>(all, at);
  sum.max_overlap_ratio = std::max(sum.max_overlap_ratio, take_gathered<double>(all, at));
}

inline Tallies sum_tallies(const std::string& all) {
  Tallies sum;
  for (std::size_t at = 0; at < all.size();) add_tallies(sum, all, at);
  return sum;
}

// Every rank's bytes, in rank order, on every rank.
inline void all_gather(const std::string& mine, MPI_Comm comm, std::string& all) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), at(static_cast<std::size_t>(size));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  std::size_t total = 0;
  for (int k = 0; k < size; ++k) {
    at[static_cast<std::size_t>(k)] = static_cast<int>(total);
    total += static_cast<std::size_t>(counts[static_cast<std::size_t>(k)]);
  }
  if (total > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw RunError(fmt::format("distributed run: {} bytes to gather at once", total));
  all.resize(total);
  MPI_Allgatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), at.data(), MPI_CHAR,
                 comm);
}
inline std::string all_gather(const std::string& mine, MPI_Comm comm) {
  std::string all;
  all_gather(mine, comm, all);
  return all;
}

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
