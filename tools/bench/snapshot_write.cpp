// How a snapshot of a scene spread over MPI ranks is best written: the
// measurement behind the choice in docs/parallel.md ("Files"). One program,
// built twice by tools/bench/snapshot_write.sh:
//  - against Debian's serial HDF5 (libhdf5-dev), it times the two gathered
//    writes: `every` (what `mpirun granule run` does: the state is gathered to
//    every rank with MPI_Allgatherv and every rank writes the whole snapshot,
//    rank 0 into the output, the others into scratch files) and `root` (the
//    state gathered to rank 0 alone, which writes it);
//  - against Debian's parallel HDF5 (libhdf5-openmpi-dev, -DSNAPSHOT_PARALLEL_HDF5),
//    `parallel`: one file opened by every rank through MPI-IO, each rank
//    writing its own rows of each dataset in one collective write.
// The snapshot holds what granule's does per particle (id, radius, position,
// velocity, spin, force, torque: 136 bytes in 3D), each rank owning
// SPHERES/ranks rows; SNAPSHOTS snapshots are written into one file, each in
// its own group, and the slowest rank's seconds per snapshot are printed.
//   usage: mpirun -np N snapshot_write_{serial,parallel} MODE SPHERES SNAPSHOTS DIR
#include <hdf5.h>
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "snapshot_write: %s failed\n", what);
  MPI_Abort(MPI_COMM_WORLD, 1);
}

// One snapshot's columns, for `rows` particles starting at global row `first`.
struct Columns {
  std::vector<std::int64_t> id;
  std::vector<double> radius, position, velocity, spin, force, torque;
  void fill(std::size_t rows, std::size_t first) {
    id.resize(rows), radius.resize(rows);
    for (auto* v : {&position, &velocity, &spin, &force, &torque}) v->resize(3 * rows);
    for (std::size_t k = 0; k < rows; ++k) {
      id[k] = static_cast<std::int64_t>(first + k);
      radius[k] = 1e-3;
      for (int a = 0; a < 3; ++a) {
        const double x = static_cast<double>(first + k) + 0.1 * a;
        position[3 * k + a] = x, velocity[3 * k + a] = -x, spin[3 * k + a] = 2 * x;
        force[3 * k + a] = 3 * x, torque[3 * k + a] = 4 * x;
      }
    }
  }
  std::vector<std::vector<double>*> vectors() {
    return {&position, &velocity, &spin, &force, &torque};
  }
};

const char* const vector_names[] = {"position", "velocity", "spin", "force", "torque"};

// Writes `rows` rows at `first` of datasets of `total` rows in group g; `xfer`
// the transfer property list (collective for MPI-IO).
void write_columns(hid_t g, Columns& c, hsize_t total, hsize_t first, hsize_t rows, hid_t xfer) {
  auto one = [&](const char* name, hid_t file_type, hid_t memory_type, int width,
                 const void* data) {
    const hsize_t dims[2] = {total, static_cast<hsize_t>(width)};
    hid_t space = H5Screate_simple(width == 1 ? 1 : 2, dims, nullptr);
    hid_t d = H5Dcreate2(g, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    check(d >= 0, "H5Dcreate2");
    const hsize_t start[2] = {first, 0}, count[2] = {rows, static_cast<hsize_t>(width)};
    H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t memory = H5Screate_simple(width == 1 ? 1 : 2, count, nullptr);
    check(H5Dwrite(d, memory_type, memory, space, xfer, data) >= 0, "H5Dwrite");
    H5Sclose(memory), H5Sclose(space), H5Dclose(d);
  };
  one("id", H5T_STD_I64LE, H5T_NATIVE_INT64, 1, c.id.data());
  one("radius", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, c.radius.data());
  auto v = c.vectors();
  for (std::size_t k = 0; k < v.size(); ++k)
    one(vector_names[k], H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 3, v[k]->data());
}

// The whole scene's columns on `root` (or on every rank, root < 0) from every
// rank's share: one gather per column, in rank order.
Columns gather(Columns& mine, std::size_t total, int root, int size) {
  Columns all;
  const bool here = root < 0 || [&] {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank == root;
  }();
  if (here) all.fill(total, 0);
  std::vector<int> counts(static_cast<std::size_t>(size)), starts(counts.size());
  auto run = [&](void* send, int count, void* receive, MPI_Datatype type) {
    MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int at = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) starts[r] = at, at += counts[r];
    if (root < 0)
      MPI_Allgatherv(send, count, type, receive, counts.data(), starts.data(), type,
                     MPI_COMM_WORLD);
    else
      MPI_Gatherv(send, count, type, receive, counts.data(), starts.data(), type, root,
                  MPI_COMM_WORLD);
  };
  const int rows = static_cast<int>(mine.id.size());
  run(mine.id.data(), rows, here ? all.id.data() : nullptr, MPI_INT64_T);
  run(mine.radius.data(), rows, here ? all.radius.data() : nullptr, MPI_DOUBLE);
  auto from = mine.vectors(), to = all.vectors();
  for (std::size_t k = 0; k < from.size(); ++k)
    run(from[k]->data(), 3 * rows, here ? to[k]->data() : nullptr, MPI_DOUBLE);
  return all;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (argc < 5) {
    if (rank == 0)
      std::fprintf(stderr, "usage: snapshot_write every|root|parallel SPHERES SNAPSHOTS DIR\n");
    MPI_Finalize();
    return 2;
  }
  const std::string mode = argv[1], dir = argv[4];
  const std::size_t total = std::strtoull(argv[2], nullptr, 10);
  const int snapshots = std::atoi(argv[3]);
  const std::size_t per = total / size, first = per * rank;
  const std::size_t rows = rank == size - 1 ? total - first : per;
  Columns mine;
  mine.fill(rows, first);

#ifdef SNAPSHOT_PARALLEL_HDF5
  if (mode != "parallel") {
    if (rank == 0) std::fprintf(stderr, "this build writes with parallel HDF5: mode parallel\n");
    MPI_Finalize();
    return 2;
  }
  hid_t access = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(access, MPI_COMM_WORLD, MPI_INFO_NULL);
  const std::string path = dir + "/parallel.h5";
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = now();
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
  check(file >= 0, "H5Fcreate");
  hid_t xfer = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE);
  for (int s = 0; s < snapshots; ++s) {
    const std::string name = "/snapshot_" + std::to_string(s);
    hid_t g = H5Gcreate2(file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    write_columns(g, mine, total, first, rows, xfer);
    H5Gclose(g);
    H5Fflush(file, H5F_SCOPE_GLOBAL);
  }
  H5Pclose(xfer);
  H5Fclose(file);
  H5Pclose(access);
#else
  if (mode != "every" && mode != "root") {
    if (rank == 0) std::fprintf(stderr, "this build writes with serial HDF5: mode every or root\n");
    MPI_Finalize();
    return 2;
  }
  const bool writer = mode == "every" || rank == 0;
  const std::string path = dir + "/" + mode + "_" + std::to_string(rank) + ".h5";
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = now();
  hid_t file = writer ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT) : -1;
  check(!writer || file >= 0, "H5Fcreate");
  for (int s = 0; s < snapshots; ++s) {
    Columns all = gather(mine, total, mode == "every" ? -1 : 0, size);
    if (!writer) continue;
    const std::string name = "/snapshot_" + std::to_string(s);
    hid_t g = H5Gcreate2(file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    write_columns(g, all, total, 0, total, H5P_DEFAULT);
    H5Gclose(g);
    H5Fflush(file, H5F_SCOPE_GLOBAL);
  }
  if (writer) H5Fclose(file);
#endif
  const double mine_seconds = now() - t0;
  double slowest = 0;
  MPI_Reduce(&mine_seconds, &slowest, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  if (rank == 0)
    std::printf(
        "mode %s ranks %d spheres %zu snapshots %d seconds_per_snapshot %.5f mb_per_s %.1f\n",
        mode.c_str(), size, total, snapshots, slowest / snapshots,
        136.0 * static_cast<double>(total) / (slowest / snapshots) / 1e6);
  MPI_Finalize();
  return 0;
}
