// The distributed step (src/parallel/distributed_run.hpp), run under mpirun on
// 1-4 ranks: every rank builds the same scene, the run keeps its share, steps,
// and the gathered state (every particle's position, velocity, spin, force and
// torque, in id order) must equal bit for bit that of the same scene run on
// one process without ranks (canonical order, one thread), which every rank
// also computes. Scenes:
//   - a 3D dense pile (linear law with friction, the batched kernel) falling
//     into a box of planes;
//   - a 3D gas of fast spheres (Hertz-Mindlin) in a box, crossing the boxes of
//     the ranks many times between rebuilds: migration with histories;
//   - a JKR agglomerate (adhesive contacts that persist past touching);
//   - a 3D pile in a drum whose cylinder wall turns (moving walls);
//   - a 2D Walton-Braun pile (the dissertation's law, latching histories).
//   - the gas again, periodic along x (walls on y and z only): particles cross
//     the period and the ranks' boxes, ghosts across the period;
//   - a pass-through while the scene's own overlaps are still being undone
//     elsewhere: let pass on every rank, as on one process.
// Then a period too short for the interaction reach is refused by name.
// Prints "mpi_distributed ok on N
// ranks" from rank 0 when every check passed on every rank; exits 1 otherwise.
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "../core/bit_identity_scenes.hpp"
#include "../core/box_walls.hpp"
#include "core/errors.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"
#include "parallel/distributed_run.hpp"

using namespace granule;
using namespace granule::parallel;
using granule::test::dense_pile;
using granule::test::jkr_agglomerate;
using granule::test::walton_braun_pile;

namespace {

int failures = 0;
int rank = 0, size = 1;

void expect(bool ok, const std::string& what) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "rank %d: FAILED %s\n", rank, what.c_str());
}

template <int D>
std::vector<double> flatten(const std::vector<GatheredParticle<D>>& state,
                            std::vector<std::int64_t>& ids) {
  std::vector<double> out;
  ids.clear();
  for (const auto& g : state) {
    ids.push_back(g.id);
    const double* parts[] = {g.position.data(), g.velocity.data(), g.force.data()};
    for (const double* v : parts) out.insert(out.end(), v, v + D);
    if constexpr (D == 2)
      out.push_back(g.spin), out.push_back(g.torque);
    else
      out.insert(out.end(), g.spin.data(), g.spin.data() + 3),
          out.insert(out.end(), g.torque.data(), g.torque.data() + 3);
  }
  return out;
}

// The one-process run: canonical order, one thread, the plain step.
template <int D>
std::vector<GatheredParticle<D>> reference(const std::function<void(Simulation<D>&)>& build,
                                           int steps) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  build(sim);
  sim.set_canonical_order(true);
  sim.set_threads(1);
  sim.advance(steps);
  std::vector<GatheredParticle<D>> out;
  const Particles<D>& p = sim.particles();
  for (const std::uint32_t k : p.in_id_order()) {
    GatheredParticle<D> g;
    g.id = p.id[k];
    g.position = p.position[k], g.velocity = p.velocity[k], g.spin = p.spin[k];
    g.force = p.force_torque[k].force, g.torque = p.force_torque[k].torque;
    out.push_back(g);
  }
  return out;
}

template <int D>
void check_scene(const char* name, const std::function<void(Simulation<D>&)>& build, int steps,
                 std::int64_t min_migrated) {
  const auto expected = reference<D>(build, steps);
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  build(sim);
  sim.set_threads(1);
  DistributedRun<D> run(sim, MPI_COMM_WORLD);
  run.advance(steps);
  const auto got = run.gather();
  std::vector<std::int64_t> ids_expected, ids_got;
  const auto a = flatten<D>(expected, ids_expected), b = flatten<D>(got, ids_got);
  expect(ids_expected == ids_got, std::string(name) + ": every particle once, the same ids");
  const bool same =
      a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  if (!same && a.size() == b.size()) {
    std::size_t first = 0;
    while (first < a.size() && std::memcmp(&a[first], &b[first], sizeof(double)) == 0) ++first;
    std::fprintf(stderr, "rank %d: %s: first difference at value %zu: %.17g vs %.17g\n", rank, name,
                 first, a[first], b[first]);
  }
  expect(same, std::string(name) + ": the gathered state equals the one-process run bit for bit");
  std::int64_t left = run.migrated(), total_left = 0;
  MPI_Allreduce(&left, &total_left, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  // With more than one rank, the scene must have moved particles between them.
  if (size > 1)
    expect(total_left >= min_migrated,
           std::string(name) + ": particles migrated (" + std::to_string(total_left) + ")");
  std::size_t ghosts = run.ghosts(), total_ghosts = 0;
  MPI_Allreduce(&ghosts, &total_ghosts, 1, MPI_UNSIGNED_LONG, MPI_SUM, MPI_COMM_WORLD);
  if (size > 1) expect(total_ghosts > 0, std::string(name) + ": ghosts exist");
  if (rank == 0)
    std::printf("%s: %zu particles, %lld migrations, %zu ghosts on rank 0, %s\n", name, got.size(),
                static_cast<long long>(total_left), run.ghosts(), run.describe().c_str());
}

void gas(Simulation<3>& sim, bool periodic_x) {
  sim.add_material({"p", 2500, 5e6, 0.3, 0});
  sim.add_material({"w", 0, 5e6, 0.3, 0});
  const ParamValues law{{"restitution", 0.7}, {"friction", 0.4}};
  sim.set_contact("p", "p", "hertz_mindlin", law);
  sim.set_contact("p", "w", "hertz_mindlin", law);
  const double side = 0.01;
  if (periodic_x) {
    sim.set_periodic(0, 0, side);
    for (int axis = 1; axis < 3; ++axis)
      for (const double sign : {1.0, -1.0}) {
        WallSpec plane;
        plane.name = std::string(sign > 0 ? "lo" : "hi") + "xyz"[axis];
        plane.material = 1;
        plane.normal = {0, 0, 0};
        plane.normal[axis] = sign;
        plane.point = {0, 0, 0};
        plane.point[axis] = sign > 0 ? 0.0 : side;
        sim.add_wall(plane);
      }
  } else {
    test::add_box_walls(sim, side, side, 1);
  }
  Random rng(3);
  const int per_row = 8;
  const double spacing = side / per_row;
  for (int a = 0; a < per_row; ++a)
    for (int b = 0; b < per_row; ++b)
      for (int c = 0; c < per_row; ++c) {
        ParticleSpec s;
        s.position = {(a + 0.5) * spacing, (b + 0.5) * spacing, (c + 0.5) * spacing};
        s.radius = 0.4 * spacing * rng.uniform(0.8, 1.0);
        s.material = 0;
        for (int d = 0; d < 3; ++d) s.velocity[d] = rng.uniform(-2.0, 2.0);
        sim.add_particle(s);
      }
  sim.set_steps_per_contact(30);
}
void fast_gas(Simulation<3>& sim) {
  gas(sim, false);
}

// The gas with x periodic over [0, 0.01) m: its two x walls become the period.
void periodic_gas(Simulation<3>& sim) {
  gas(sim, true);
}

void drum(Simulation<3>& sim) {
  sim.add_material({"p", 2500, 5e6, 0.3, 0});
  sim.add_material({"w", 7800, 5e6, 0.3, 0});
  const ParamValues law{{"restitution", 0.6}, {"friction", 0.5}};
  sim.set_contact("p", "p", "hertz_mindlin", law);
  sim.set_contact("p", "w", "hertz_mindlin", law);
  const double radius = 0.006, depth = 0.004;
  WallSpec shell;
  shell.name = "drum";
  shell.type = WallType::cylinder;
  shell.material = 1;
  shell.center = {0, 0, 0};
  shell.axis = {0, 0, 1};
  shell.radius = radius;
  shell.inside = true;
  shell.angular_velocity = 30;  // rad/s
  sim.add_wall(shell);
  for (const double sign : {1.0, -1.0}) {
    WallSpec cap;
    cap.name = sign > 0 ? "back" : "front";
    cap.material = 1;
    cap.normal = {0, 0, sign};
    cap.point = {0, 0, sign > 0 ? 0.0 : depth};
    sim.add_wall(cap);
  }
  FillSpec f;
  f.shape = RegionShape::box;
  f.lo = {-0.7 * radius, -0.7 * radius, 0}, f.hi = {0.7 * radius, 0.0, depth};
  f.count = 300;
  f.radius_min = 0.25e-3, f.radius_max = 0.3e-3;
  f.material = 0;
  f.seed = 2;
  f.allow_overlap = true;
  sim.fill(f);
  sim.set_gravity({0, -9.81, 0});
}

// The grace of the scene's own overlaps (check_overlaps) is the whole scene's:
// two spheres started 1.9 r deep into each other on one side, still pushing
// apart, while on the other side C and D (their pairs under overlap_warning
// for the first steps) then pass through each other: one process lets that
// pass (the scene's overlaps are still being undone), and so must the rank
// that holds C and D, whose own pairs were all under the warning before.
void grace(Simulation<3>& sim) {
  const double r = 0.2e-3, k = 2e4, density = 1200;
  sim.add_material({"m", density, 0, 0, 0});
  sim.set_contact("m", "m", "linear", {{"k_normal", k}, {"restitution", 0.85}});
  const double mass = 4.0 / 3.0 * 3.141592653589793 * r * r * r * density;
  const double omega = std::sqrt(k / (mass / 2));
  auto add = [&](double x, double y, double vx) {
    ParticleSpec s;
    s.position = {x, y, 0};
    s.velocity = {vx, 0, 0};
    s.radius = r;
    s.material = 0;
    sim.add_particle(s);
  };
  add(-2 * r, 0.05 * r, 0), add(-2 * r, -0.05 * r, 0);
  const double v = 10 * r * omega;  // 0.8 r a step closer at dt = t_c / 40
  add(0.5 * r, 0, v / 2), add(4.5 * r, 0, -v / 2);
}

// A scene's error may be one rank's alone, with the others inside the step's
// collectives: it ends them all (the message first) rather than leave them waiting.
template <typename F>
void guarded(const char* name, F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    expect(false, std::string(name) + ": " + e.what());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (argc > 2) {  // one scene for a given number of steps: mpi_distributed_test drum 100
    const std::string which = argv[1];
    const int steps = std::atoi(argv[2]);
    if (which == "drum") guarded("drum", [&] { check_scene<3>("drum", drum, steps, 0); });
    if (which == "gas") guarded("gas", [&] { check_scene<3>("gas", fast_gas, steps, 0); });
    if (which == "pile") guarded("pile", [&] { check_scene<3>("pile", dense_pile, steps, 0); });
    MPI_Finalize();
    return failures == 0 ? 0 : 1;
  }
  guarded("dense pile", [] { check_scene<3>("dense pile (linear)", dense_pile, 400, 1); });
  guarded("gas", [] { check_scene<3>("fast gas (Hertz-Mindlin)", fast_gas, 1500, 50); });
  guarded("jkr", [] { check_scene<3>("JKR agglomerate", jkr_agglomerate, 600, 0); });
  guarded("drum", [] { check_scene<3>("turning drum (Hertz-Mindlin)", drum, 1500, 1); });
  guarded("wb", [] { check_scene<2>("2D pile (Walton-Braun)", walton_braun_pile, 800, 1); });
  guarded("periodic gas", [] { check_scene<3>("periodic gas (x)", periodic_gas, 1500, 50); });
  guarded("grace", [] { check_scene<3>("the scene's overlaps' grace", grace, 60, 0); });
  // A period under twice the reach (2 mm against spheres up to 1 mm across
  // and the skin) is refused by name, not run wrongly.
  {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    periodic_gas(sim);
    sim.set_periodic(0, 0, 0.002);
    bool refused = false;
    try {
      DistributedRun<3> run(sim, MPI_COMM_WORLD);
    } catch (const InputError& e) {
      refused = std::string(e.what()).find("periodic length") != std::string::npos;
    }
    expect(refused, "a period under twice the reach is refused");
  }
  int mine = failures, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0 && all == 0) std::printf("mpi_distributed ok on %d ranks\n", size);
  MPI_Finalize();
  return all == 0 ? 0 : 1;
}
