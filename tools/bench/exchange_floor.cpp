// What one exchange of N doubles each way between two ranks costs on this
// machine, the floor under a spread run's per-step ghost forward
// (docs/parallel.md): by messages (MPI_Irecv, MPI_Isend, MPI_Waitall, as
// forward_ghosts sends them) and through an MPI-3 shared window as
// SharedForward uses it (each rank writes its part's half of this round, the
// ranks meet, each reads the other's; the halves alternate), the ranks
// meeting at MPI_Barrier and, as SharedForward meets them, by flags.
//
//   cmake --build build --target exchange_floor
//   mpirun --allow-run-as-root -np 2 build/exchange_floor [N ...]   (default 1 60 300 600 1200)
#include <mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

constexpr int rounds = 100000;

double by_messages(int other, int n) {
  std::vector<double> out(static_cast<std::size_t>(n), 1.0), in(static_cast<std::size_t>(n));
  MPI_Request requests[2];
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  for (int r = 0; r < rounds; ++r) {
    MPI_Irecv(in.data(), n, MPI_DOUBLE, other, 5, MPI_COMM_WORLD, &requests[0]);
    MPI_Isend(out.data(), n, MPI_DOUBLE, other, 5, MPI_COMM_WORLD, &requests[1]);
    MPI_Waitall(2, requests, MPI_STATUSES_IGNORE);
  }
  return (MPI_Wtime() - t0) / rounds;
}

// Each rank's part of a shared window: a cache line for a flag, then two
// halves of n doubles, used on alternate rounds.
struct SharedPair {
  static constexpr std::size_t flag_doubles = 8;
  MPI_Win window;
  double* mine = nullptr;
  double* theirs = nullptr;
  SharedPair(int other, int n) {
    MPI_Win_allocate_shared(static_cast<MPI_Aint>((flag_doubles + 2 * n) * sizeof(double)),
                            sizeof(double), MPI_INFO_NULL, MPI_COMM_WORLD, &mine, &window);
    MPI_Aint bytes = 0;
    int unit = 0;
    MPI_Win_shared_query(window, other, &bytes, &unit, &theirs);
    MPI_Win_lock_all(MPI_MODE_NOCHECK, window);
    __atomic_store_n(flag(mine), std::uint64_t{0}, __ATOMIC_RELEASE);
    MPI_Barrier(MPI_COMM_WORLD);
  }
  ~SharedPair() {
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Win_unlock_all(window);
    MPI_Win_free(&window);
  }
  static std::uint64_t* flag(double* part) { return reinterpret_cast<std::uint64_t*>(part); }
};

// Through the shared window, the ranks meeting at MPI_Barrier (with
// MPI_Win_sync on each side) or, as SharedForward::meet does, by flags: each
// stores its round number into its own flag after writing (release) and
// waits, pausing, until the other's has reached it (acquire).
double by_shared_window(int other, int n, bool by_flags) {
  SharedPair pair(other, n);
  std::vector<double> out(static_cast<std::size_t>(n), 1.0), in(static_cast<std::size_t>(n));
  const double t0 = MPI_Wtime();
  for (int r = 0; r < rounds; ++r) {
    const std::size_t half =
        SharedPair::flag_doubles + static_cast<std::size_t>(r % 2) * out.size();
    std::memcpy(pair.mine + half, out.data(), out.size() * sizeof(double));
    if (by_flags) {
      const std::uint64_t round = static_cast<std::uint64_t>(r) + 1;
      __atomic_store_n(SharedPair::flag(pair.mine), round, __ATOMIC_RELEASE);
      while (__atomic_load_n(SharedPair::flag(pair.theirs), __ATOMIC_ACQUIRE) < round)
        __builtin_ia32_pause();
    } else {
      MPI_Win_sync(pair.window);
      MPI_Barrier(MPI_COMM_WORLD);
      MPI_Win_sync(pair.window);
    }
    std::memcpy(in.data(), pair.theirs + half, in.size() * sizeof(double));
  }
  return (MPI_Wtime() - t0) / rounds;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size != 2) {
    if (rank == 0) std::fprintf(stderr, "exchange_floor: run it on 2 ranks (mpirun -np 2)\n");
    MPI_Finalize();
    return 2;
  }
  std::vector<int> counts;
  for (int a = 1; a < argc; ++a) counts.push_back(std::atoi(argv[a]));
  if (counts.empty()) counts = {1, 60, 300, 600, 1200};
  if (rank == 0)
    std::printf(
        "doubles each way | messages [us] | shared window [us] | shared window, flags [us]\n");
  for (const int n : counts) {
    if (n < 1) continue;
    const double messages = by_messages(1 - rank, n);
    const double shared = by_shared_window(1 - rank, n, false);
    const double flags = by_shared_window(1 - rank, n, true);
    if (rank == 0)
      std::printf("%d | %.2f | %.2f | %.2f\n", n, messages * 1e6, shared * 1e6, flags * 1e6);
  }
  MPI_Finalize();
  return 0;
}
