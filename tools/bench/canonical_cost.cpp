// What the canonical order (SimulationBase::set_canonical_order) costs the
// pair loop when the storage is kept along the Morton curve: a box of
// per_side^2 x layers spheres (r = 1 mm, a lattice 1 % closer than touching,
// linear law with friction, gravity), its ids given along the lattice rows or
// scattered at random over the sites, the storage re-sorted along the curve
// (Simulation::sort_particles) and `steps` steps timed, canonical order off and
// on in turn. Prints the pair loop's nanoseconds per pair contact and step
// (the force stage less walls and fixed-order sums, as box3d_compare.lua) and
// the time of one list rebuild.
//
//   cmake --build build --target canonical_cost
//   build/canonical_cost [per_side=25] [layers=40] [steps=500] [rounds=2]
//
// Not a test (timings are noisy on a shared machine); docs/parallel.md
// ("Canonical order") records its numbers.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <random>
#include <vector>

#include "engine/simulation.hpp"

using namespace granule;

namespace {

struct Timing {
  double pair_ns = 0;    // per pair contact and step
  double rebuild_s = 0;  // one re-sort and list rebuild
  std::int64_t contacts = 0;
};

Timing run(int per_side, int layers, int steps, bool scattered_ids, bool canonical) {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  const ParamValues law{{"k_normal", 1e4}, {"restitution", 0.5}, {"friction", 0.5}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "w", "linear", law);
  sim.set_time_step(1.5e-6);
  const double r = 1e-3, spacing = 1.98 * r, side = per_side * spacing + 0.02 * r;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      if (axis == 2 && sign < 0) continue;  // open top
      WallSpec w;
      w.name = fmt::format("w{}{}", axis, sign > 0 ? "lo" : "hi");
      w.material = 1;
      w.normal[axis] = sign;
      if (sign < 0) w.point[axis] = side;
      sim.add_wall(w);
    }
  }
  std::vector<std::array<int, 3>> sites;
  for (int c = 0; c < layers; ++c)
    for (int b = 0; b < per_side; ++b)
      for (int a = 0; a < per_side; ++a) sites.push_back({a, b, c});
  if (scattered_ids) std::shuffle(sites.begin(), sites.end(), std::mt19937(1));
  for (const auto& s : sites) {
    ParticleSpec p;
    p.position = {(s[0] + 0.5) * spacing, (s[1] + 0.5) * spacing, (s[2] + 0.5) * spacing};
    p.radius = r;
    p.material = 0;
    sim.add_particle(p);
  }
  sim.set_gravity({0, 0, -9.81});
  sim.set_canonical_order(canonical);
  sim.advance(1);
  const auto sorted = std::chrono::steady_clock::now();
  sim.sort_particles();  // storage along the curve, lists rebuilt (in canonical order if on)
  Timing t;
  t.rebuild_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - sorted).count();
  sim.advance(100);
  const auto before = sim.stage_times();
  std::int64_t contacts = 0;
  for (int s = 0; s < steps; s += 10) {
    sim.advance(10);
    contacts += 10 * sim.stats().contacts_particle;
  }
  const auto after = sim.stage_times();
  const double pair_s = (after.force - before.force) - (after.walls - before.walls) -
                        (after.scatter - before.scatter);
  t.pair_ns = 1e9 * pair_s / static_cast<double>(std::max<std::int64_t>(1, contacts));
  t.contacts = sim.stats().contacts_particle;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const int per_side = argc > 1 ? std::atoi(argv[1]) : 25;
  const int layers = argc > 2 ? std::atoi(argv[2]) : 40;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 500;
  const int rounds = argc > 4 ? std::atoi(argv[4]) : 2;
  fmt::print("{} spheres, {} steps per run, one thread\n", per_side * per_side * layers, steps);
  for (int round = 1; round <= rounds; ++round)
    for (const bool scattered : {false, true})
      for (const bool canonical : {false, true}) {
        const Timing t = run(per_side, layers, steps, scattered, canonical);
        fmt::print(
            "round {} ids {:9} canonical {:3}: pair loop {:.1f} ns per pair contact, "
            "re-sort and rebuild {:.3f} s, {} pair contacts\n",
            round, scattered ? "scattered" : "in rows", canonical ? "on" : "off", t.pair_ns,
            t.rebuild_s, t.contacts);
        std::fflush(stdout);
      }
}
