// Strong and weak scaling of the distributed step (src/parallel/distributed_run.hpp):
// a 3D scene of spheres (SCENE=shear, the default: a periodic shear cell in its
// steady state; SCENE=burst: a lattice box whose overlaps burst, a transient)
// stepped over the ranks of mpirun for WARMUP steps (default 10000), then timed
// over STEPS. Prints one line from rank 0: ranks, spheres, spheres per rank,
// steps, seconds, particle-steps/s, the slowest rank's time split into compute,
// ghost forwarding, waiting and rebuilds (migration, new ghosts and lists), the
// ghosts per owned particle, the migrations and re-cuts of the timed steps, the
// contacts per sphere and kinetic energy per sphere at the end; with one rank
// (unless PLAIN=0) also the same scene stepped without the run (the cost of the
// distributed machinery).
//
//   cmake --build build --target distributed_scaling
//   mpirun --allow-run-as-root --oversubscribe -np N build/distributed_scaling MODE PER_SIDE STEPS
// MODE strong: PER_SIDE^3 spheres whatever N; weak: PER_SIDE^3 spheres per rank
// (the box N times longer along x). Other settings from the environment (pass
// them to every rank with mpirun -x): SPACING, WALL_SPEED (the shear cell),
// REBALANCE_THRESHOLD (default 1.1). tools/bench/distributed_scaling.sh runs
// both modes over 1, 2 and 4 ranks and writes the table.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/random.hpp"
#include "engine/simulation.hpp"
#include "parallel/distributed_run.hpp"

using namespace granule;

namespace {

// Settings from the environment (the bench's knobs, documented at the top).
double setting(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

// The spheres' material and linear law with friction, and the walls'.
void linear_materials(Simulation<3>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  const ParamValues law{{"k_normal", 2e3}, {"restitution", 0.5}, {"friction", 0.4}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "w", "linear", law);
}

// Two planes facing each other across `axis`, at `lo` and `hi` along it,
// moving at `lo_velocity` and `hi_velocity` (in their planes).
void wall_pair(Simulation<3>& sim, int axis, double lo_at, double hi_at,
               const Triple& lo_velocity = {}, const Triple& hi_velocity = {}) {
  WallSpec lo, hi;
  lo.name = "lo" + std::to_string(axis), hi.name = "hi" + std::to_string(axis);
  lo.material = hi.material = 1;
  lo.normal = hi.normal = {0, 0, 0};
  lo.normal[axis] = 1, hi.normal[axis] = -1;
  lo.point = {0, 0, 0}, hi.point = {0, 0, 0};
  lo.point[axis] = lo_at, hi.point[axis] = hi_at;
  lo.velocity = lo_velocity, hi.velocity = hi_velocity;
  sim.add_wall(lo), sim.add_wall(hi);
}

// Spheres of radius r on an nx x ny x nz lattice, `spacing` apart, the first
// at (offset, offset, offset) * spacing, with random velocities of up to
// 0.05 m/s along each axis.
void lattice(Simulation<3>& sim, int nx, int ny, int nz, double r, double spacing, double offset) {
  Random rng(7);
  for (int a = 0; a < nx; ++a)
    for (int b = 0; b < ny; ++b)
      for (int c = 0; c < nz; ++c) {
        ParticleSpec s;
        s.position = {(a + offset) * spacing, (b + offset) * spacing, (c + offset) * spacing};
        s.radius = r;
        s.material = 0;
        for (int d = 0; d < 3; ++d) s.velocity[d] = rng.uniform(-0.05, 0.05);
        sim.add_particle(s);
      }
  sim.set_threads(1);
}

// A periodic shear cell: spheres on a lattice SPACING radii apart (default
// 1.95: a dense packing, 5 % overlapping at the start), periodic along x, held
// between side walls in y and two plates in z that slide along x at
// +-WALL_SPEED (default 0.5 m/s), no gravity. After the start's overlaps have
// relaxed the cell shears in a steady state: the contacts, the rebuild rate
// and the particles crossing the x cuts stay level, so that a short timed
// window measures what a long run would.
void shear_cell(Simulation<3>& sim, int nx, int ny, int nz) {
  linear_materials(sim);
  const double r = 0.5e-3, spacing = setting("SPACING", 1.95) * r;
  const double speed = setting("WALL_SPEED", 0.5);
  sim.set_periodic(0, 0.0, nx * spacing);
  wall_pair(sim, 1, 0, ny * spacing);
  wall_pair(sim, 2, 0, nz * spacing, {-speed, 0, 0}, {speed, 0, 0});
  lattice(sim, nx, ny, nz, r, spacing, 0.5);
}

// SCENE=burst: the lattice box of spheres 1.98 radii apart in a closed box
// with gravity, jostled by random velocities: a transient (the start's
// overlaps burst, the spheres fly, collide and cool), whose cost per particle
// falls twenty-fold within a few thousand steps while the cut follows it.
void burst_box(Simulation<3>& sim, int nx, int ny, int nz) {
  linear_materials(sim);
  const double r = 0.5e-3, spacing = 1.98 * r;
  const double extent[3] = {nx * spacing, ny * spacing, 2 * nz * spacing};
  for (int axis = 0; axis < 3; ++axis) wall_pair(sim, axis, -r, extent[axis]);
  lattice(sim, nx, ny, nz, r, spacing, 0);
  sim.set_gravity({0, 0, -9.81});
}

// The scene SCENE names (default shear).
void make_scene(Simulation<3>& sim, int nx, int ny, int nz) {
  const char* scene = std::getenv("SCENE");
  const std::string name = scene ? scene : "shear";
  if (name == "shear") return shear_cell(sim, nx, ny, nz);
  if (name == "burst") return burst_box(sim, nx, ny, nz);
  throw std::runtime_error("SCENE: shear or burst, not '" + name + "'");
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
  if (argc < 4) {
    if (rank == 0) std::fprintf(stderr, "usage: distributed_scaling strong|weak PER_SIDE STEPS\n");
    MPI_Finalize();
    return 2;
  }
  const std::string mode = argv[1];
  const int side = std::atoi(argv[2]);
  const long steps = std::atol(argv[3]);
  const int nx = mode == "weak" ? side * size : side;
  const long warmup = static_cast<long>(setting("WARMUP", 10000));
  Simulation<3> sim;
  make_scene(sim, nx, side, side);
  parallel::DistributedRun<3> run(sim, MPI_COMM_WORLD, setting("REBALANCE_THRESHOLD", 1.1));
  run.advance(warmup);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto before = run.times();
  const long long migrated_before = run.migrated(), recuts_before = run.recuts();
  const double t0 = now();
  run.advance(steps);
  MPI_Barrier(MPI_COMM_WORLD);
  const double seconds = now() - t0;
  const auto after = run.times();
  double mine[4] = {after.compute - before.compute, after.exchange - before.exchange,
                    after.waiting - before.waiting, after.rebuild - before.rebuild};
  double most[4];
  MPI_Reduce(mine, most, 4, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  const long long rebuilds = after.rebuilds - before.rebuilds;
  double ghosts = static_cast<double>(run.ghosts()), owned = static_cast<double>(run.owned());
  double sums[2] = {ghosts, owned}, total[2];
  MPI_Reduce(sums, total, 2, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  long long migrated = run.migrated() - migrated_before, migrated_all = 0;
  MPI_Reduce(&migrated, &migrated_all, 1, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  const long long n = run.global_particles();
  const GlobalStats totals = run.totals();
  // One rank: the same scene stepped by the plain engine, for the run's overhead.
  double plain = 0;
  if (size == 1 && setting("PLAIN", 1) != 0) {
    Simulation<3> alone;
    make_scene(alone, nx, side, side);
    alone.set_canonical_order(true);
    alone.advance(warmup);
    const double t1 = now();
    alone.advance(steps);
    plain = now() - t1;
  }
  if (rank == 0) {
    std::printf(
        "mode %s ranks %d spheres %lld per_rank %.0f steps %ld seconds %.4f "
        "particle_steps_per_s %.4g compute_s %.4f exchange_s %.4f waiting_s %.4f "
        "ghosts_per_owned %.4f migrations %lld recuts %lld rebuild_s %.4f rebuilds %lld "
        "contacts_per_particle %.3f kinetic_j_per_particle %.3g",
        mode.c_str(), size, n, static_cast<double>(n) / size, steps, seconds,
        static_cast<double>(n) * static_cast<double>(steps) / seconds, most[0], most[1], most[2],
        total[0] / std::max(1.0, total[1]), migrated_all,
        static_cast<long long>(run.recuts() - recuts_before), most[3], rebuilds,
        static_cast<double>(totals.contacts_particle + totals.contacts_wall) /
            static_cast<double>(n),
        (totals.kinetic_translational + totals.kinetic_rotational) / static_cast<double>(n));
    if (size == 1 && plain > 0)
      std::printf(" plain_seconds %.4f overhead %.4f", plain, seconds / plain - 1);
    std::printf("\n");
  }
  MPI_Finalize();
  return 0;
}
