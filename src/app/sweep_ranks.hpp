// The MPI side of `granule sweep`: whether the program runs under a launcher,
// and the messages by which rank 0 hands out cases and workers report back.
#pragma once

#include <cstdlib>
#include <iostream>
#include <string>

#include "app/sweep_types.hpp"

#ifdef GRANULE_HAVE_MPI
#include <mpi.h>
#endif

namespace granule::app::sweep_detail {

// MPI when the program was started by a launcher (mpirun, mpiexec); otherwise none, so
// that a plain `granule sweep` never waits on an MPI start-up it does not need.
class Ranks {
 public:
  Ranks() {
#ifdef GRANULE_HAVE_MPI
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") ||
        std::getenv("PMI_RANK")) {
      MPI_Init(nullptr, nullptr);
      active_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
      MPI_Comm node;
      MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
      MPI_Comm_size(node, &node_size_);
      MPI_Comm_free(&node);
    }
#else
    // Started by a launcher but built without MPI: every rank would run every case into the
    // same files. The first runs them all; the others leave at once.
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
      if (const char* r = std::getenv(name); r && std::atoi(r) > 0) {
        idle_ = true;
        return;
      }
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"))
      std::cerr << "granule sweep: this granule was built without MPI; rank 0 runs every case\n";
#endif
  }
  ~Ranks() {
#ifdef GRANULE_HAVE_MPI
    if (active_) MPI_Finalize();
#endif
  }
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  int rank() const {
    return rank_;
  }
  int size() const {
    return size_;
  }
  int per_node() const {
    return node_size_;
  }
  bool idle() const {  // a rank with nothing to do (a launcher, but built without MPI)
    return idle_;
  }
  // After an error on one rank: the others may be waiting on it, so end them all.
  void abort() const {
#ifdef GRANULE_HAVE_MPI
    if (active_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, 1);
#endif
  }

#ifdef GRANULE_HAVE_MPI
  static constexpr int tag_request = 1, tag_assign = 2;
  // Worker: reports the last outcome (empty at first) and gets the next case, or -1.
  long long ask(const std::string& report) const {
    MPI_Send(report.data(), static_cast<int>(report.size()), MPI_CHAR, 0, tag_request,
             MPI_COMM_WORLD);
    long long index = -1;
    MPI_Recv(&index, 1, MPI_LONG_LONG, 0, tag_assign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return index;
  }
  // Rank 0: a worker's request if one is waiting: its rank and report.
  bool take_request(int& from, std::string& report) const {
    int waiting = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, tag_request, MPI_COMM_WORLD, &waiting, &status);
    if (!waiting) return false;
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    report.assign(static_cast<std::size_t>(length), '\0');
    MPI_Recv(report.data(), length, MPI_CHAR, status.MPI_SOURCE, tag_request, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    from = status.MPI_SOURCE;
    return true;
  }
  void assign(int to, long long index) const {
    MPI_Send(&index, 1, MPI_LONG_LONG, to, tag_assign, MPI_COMM_WORLD);
  }
#endif

 private:
  bool active_ = false, idle_ = false;
  int rank_ = 0, size_ = 1, node_size_ = 1;
};

#ifdef GRANULE_HAVE_MPI
// A worker's report of a case's outcome as one message, and back.
std::string encode(const Outcome& o);
Outcome decode(const std::string& text);
#endif

}  // namespace granule::app::sweep_detail
