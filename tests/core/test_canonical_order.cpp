// Canonical order (SimulationBase::set_canonical_order): one scene stored in
// natural, reversed and shuffled particle order, on one and two threads, ends
// in the same state bit for bit, particle by particle id; without it the
// storage order changes the sums, and so the bits. A checkpoint keeps the
// setting, and the lists' order with it.
#include <catch2/catch.hpp>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "../geometry/mesh_helpers.hpp"
#include "bit_identity_scenes.hpp"
#include "box_walls.hpp"
#include "core/errors.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

using namespace granule;
using granule::test::dense_pile;

namespace {
enum class Storage { natural, reversed, shuffled };

std::vector<std::int64_t> storage_ids(std::vector<std::int64_t> ids, Storage order, unsigned seed) {
  if (order == Storage::reversed) std::reverse(ids.begin(), ids.end());
  if (order == Storage::shuffled) std::shuffle(ids.begin(), ids.end(), std::mt19937(seed));
  return ids;
}

// What a run ends in, particle by particle in id order: position, velocity,
// spin and last force; then the totals and the reactions on the walls.
struct Outcome {
  std::vector<double> particles, totals;
  std::int64_t pair_contacts = 0, wall_contacts = 0;
};

template <int D>
Outcome outcome(const Simulation<D>& sim) {
  Outcome o;
  const auto ids = sim.particle_ids();
  std::vector<std::int64_t> sorted(ids);
  std::sort(sorted.begin(), sorted.end());
  for (const std::int64_t id : sorted)
    for (const Triple& t : {sim.position(id), sim.velocity(id), sim.spin(id), sim.force(id)})
      o.particles.insert(o.particles.end(), t.begin(), t.end());
  const GlobalStats g = sim.stats();
  o.totals = {g.kinetic_translational, g.kinetic_rotational, g.momentum[0],
              g.momentum[1],           g.momentum[2],        g.angular_momentum_z};
  for (int w = 0; w < sim.wall_count(); ++w) {
    const Triple f = sim.wall_force(w);
    o.totals.insert(o.totals.end(), {f[0], f[1], f[2], sim.wall_axial_torque(w)});
  }
  o.pair_contacts = g.contacts_particle, o.wall_contacts = g.contacts_wall;
  return o;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Runs the scene `build` makes for `steps` steps in storage order `order`, on
// `threads` threads (the parallel paths taken on small scenes). A shuffled run
// is stored anew halfway (histories carried by id through the rebuilt lists).
template <int D>
Outcome run(const std::function<void(Simulation<D>&)>& build, Storage order, int threads,
            bool canonical, int steps) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  build(sim);
  sim.set_canonical_order(canonical);
  sim.set_threads(threads);
  sim.set_parallel_thresholds(256, 128);
  sim.reorder_storage(storage_ids(sim.particle_ids(), order, 11));
  if (order == Storage::shuffled) {
    sim.advance(steps / 2);
    sim.reorder_storage(storage_ids(sim.particle_ids(), order, 23));
    sim.advance(steps - steps / 2);
  } else {
    sim.advance(steps);
  }
  REQUIRE(sim.canonical_order() == canonical);
  return outcome(sim);
}

// Every storage order and team against natural order on one thread.
template <int D>
void check_canonical(const std::function<void(Simulation<D>&)>& build, int steps,
                     std::int64_t min_pair_contacts, std::int64_t min_wall_contacts) {
  const Outcome reference = run<D>(build, Storage::natural, 1, true, steps);
  INFO("pair contacts " << reference.pair_contacts << ", wall contacts "
                        << reference.wall_contacts);
  REQUIRE(reference.pair_contacts >= min_pair_contacts);
  REQUIRE(reference.wall_contacts >= min_wall_contacts);
  for (const Storage order : {Storage::natural, Storage::reversed, Storage::shuffled})
    for (const int threads : {1, 2}) {
      if (order == Storage::natural && threads == 1) continue;
      const Outcome other = run<D>(build, order, threads, true, steps);
      INFO("storage order " << static_cast<int>(order) << ", threads " << threads);
      CHECK(same_bits(reference.particles, other.particles));
      CHECK(same_bits(reference.totals, other.totals));
      CHECK(reference.pair_contacts == other.pair_contacts);
    }
}

}  // namespace

TEST_CASE("canonical: a 3D dense pile (linear, batched) is bit-identical in any storage order",
          "[canonical]") {
  const std::function<void(Simulation<3>&)> build = [](Simulation<3>& sim) {
    dense_pile(sim);
    REQUIRE(sim.particle_count() == 700);
  };
  check_canonical<3>(build, 400, 200, 40);
  // The batched kernel computed the pairs.
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  dense_pile(sim);
  sim.set_canonical_order(true);
  sim.advance(10);
  CHECK(sim.stats().contacts_batched == sim.stats().contacts_particle);
}

TEST_CASE("canonical: a 3D periodic gas (Hertz-Mindlin) is bit-identical in any storage order",
          "[canonical]") {
  const std::function<void(Simulation<3>&)> build = [](Simulation<3>& sim) {
    sim.add_material({"p", 2500, 5e6, 0.3, 0});
    sim.add_material({"w", 0, 5e6, 0.3, 0});
    const ParamValues law{{"restitution", 0.7}, {"friction", 0.4}};
    sim.set_contact("p", "p", "hertz_mindlin", law);
    sim.set_contact("p", "w", "hertz_mindlin", law);
    // Periodic along x; walls across y and z.
    const double side = 0.01;
    sim.set_periodic(0, 0, side);
    test::add_walls_across(sim, 1, side, 1);
    Random rng(3);
    const int per_row = 8;
    const double spacing = side / per_row;
    for (int a = 0; a < per_row; ++a)
      for (int b = 0; b < per_row; ++b)
        for (int c = 0; c < per_row; ++c) {
          ParticleSpec s;
          s.position = {(a + 0.5) * spacing, (b + 0.5) * spacing, (c + 0.5) * spacing};
          s.radius = 0.45 * spacing * rng.uniform(0.8, 1.0);
          s.material = 0;
          for (int d = 0; d < 3; ++d) s.velocity[d] = rng.uniform(-0.5, 0.5);
          sim.add_particle(s);
        }
    sim.set_steps_per_contact(30);
  };
  // Fast enough to cross the periodic boundary and rebuild the lists often.
  check_canonical<3>(build, 1500, 5, 1);
}

TEST_CASE("canonical: a JKR agglomerate (adhesive) is bit-identical in any storage order",
          "[canonical]") {
  const std::function<void(Simulation<3>&)> build = test::jkr_agglomerate;
  check_canonical<3>(build, 600, 200, 0);
}

TEST_CASE("canonical: a 3D pile on a turning mesh floor is bit-identical in any storage order",
          "[canonical][mesh]") {
  // Mesh-wall contacts take the wall lists' path (one candidate per part):
  // a pile in a square of planes, on a triangulated floor that turns about z.
  const std::function<void(Simulation<3>&)> build = [](Simulation<3>& sim) {
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.add_material({"w", 0, 0, 0, 0});
    const ParamValues law{{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
    sim.set_contact("p", "p", "linear", law);
    sim.set_contact("p", "w", "linear", law);
    const double half = 0.004;
    for (int axis = 0; axis < 2; ++axis)
      for (const double sign : {1.0, -1.0}) {
        WallSpec w;
        w.name = "side" + std::to_string(axis) + (sign > 0 ? "lo" : "hi");
        w.material = 1;
        w.normal[axis] = sign;
        w.point[axis] = -sign * half;
        sim.add_wall(w);
      }
    io::TriangleMesh floor = test::flat_grid(2 * half, 6);
    io::MeshFileReport report;
    io::clean_mesh(floor, report);
    MeshWallSpec spec;
    spec.name = "floor";
    spec.file = "(memory)";
    spec.material = 1;
    spec.angular_velocity = 20;  // rad/s about z through the origin
    sim.add_mesh_wall(spec, std::move(floor));
    FillSpec pile;
    pile.shape = RegionShape::box;
    pile.lo = {-half, -half, 0}, pile.hi = {half, half, 0.004};
    pile.count = 400;
    pile.radius_min = 0.3e-3, pile.radius_max = 0.4e-3;
    pile.material = 0;
    pile.seed = 9;
    pile.allow_overlap = true;
    sim.fill(pile);
    sim.set_gravity({0, 0, -9.81});
  };
  check_canonical<3>(build, 400, 60, 30);
}

TEST_CASE("canonical: a 2D Walton-Braun pile is bit-identical in any storage order",
          "[canonical]") {
  const std::function<void(Simulation<2>&)> build = test::walton_braun_pile;
  check_canonical<2>(build, 800, 80, 10);
}

TEST_CASE("canonical: without it the storage order changes the bits", "[canonical]") {
  // The test above can fail: the same pile, reversed, with the sums in slot
  // order as the cell grid lists them, ends elsewhere in the last bits.
  const std::function<void(Simulation<3>&)> build = dense_pile;
  const Outcome natural = run<3>(build, Storage::natural, 1, false, 400);
  const Outcome reversed = run<3>(build, Storage::reversed, 1, false, 400);
  REQUIRE(natural.particles.size() == reversed.particles.size());
  CHECK_FALSE(same_bits(natural.particles, reversed.particles));
  // Round-off, not another physics: the pile's kinetic energy agrees to 1e-3.
  CHECK(reversed.totals[0] == Approx(natural.totals[0]).epsilon(1e-3));
}

TEST_CASE("canonical: a checkpoint keeps the setting and continues bit for bit", "[canonical]") {
  auto fresh = [](bool canonical) {
    auto sim = std::make_unique<Simulation<3>>();
    sim->set_warning_handler([](const std::string&) {});
    dense_pile(*sim);
    sim->set_canonical_order(canonical);
    return sim;
  };
  auto whole = fresh(true);
  whole->reorder_storage(storage_ids(whole->particle_ids(), Storage::shuffled, 5));
  whole->advance(150);
  const StateBlob saved = whole->save_state();
  REQUIRE(saved.integers.at("canonical_order") == std::vector<std::int64_t>{1});
  whole->advance(150);
  // The restarted scene does not ask for the setting: the checkpoint brings it.
  auto resumed = fresh(false);
  resumed->load_state(saved);
  CHECK(resumed->canonical_order());
  resumed->advance(150);
  const Outcome a = outcome(*whole), b = outcome(*resumed);
  CHECK(same_bits(a.particles, b.particles));
  CHECK(same_bits(a.totals, b.totals));
  // And both agree with a natural-order run that never stopped.
  auto natural = fresh(true);
  natural->advance(300);
  CHECK(same_bits(outcome(*natural).particles, a.particles));

  // Off is kept as off; a checkpoint from before the setting loads as off; a
  // damaged value is refused by name.
  auto plain = fresh(false);
  plain->advance(5);
  StateBlob off = plain->save_state();
  REQUIRE(off.integers.at("canonical_order") == std::vector<std::int64_t>{0});
  auto again = fresh(true);
  again->load_state(off);
  CHECK_FALSE(again->canonical_order());
  off.integers.erase("canonical_order");
  auto older = fresh(true);
  older->load_state(off);
  CHECK_FALSE(older->canonical_order());
  off.integers["canonical_order"] = {2};
  auto damaged = fresh(false);
  CHECK_THROWS_WITH(damaged->load_state(off), Catch::Contains("'canonical_order'"));
}

TEST_CASE("canonical: reorder_storage refuses a list that is not the particles' ids",
          "[canonical]") {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  dense_pile(sim);
  auto ids = sim.particle_ids();
  ids.pop_back();
  CHECK_THROWS_WITH(sim.reorder_storage(ids), Catch::Contains("'ids' names 699 particles"));
  ids.push_back(ids.front());
  CHECK_THROWS_AS(sim.reorder_storage(ids), InputError);
  CHECK_THROWS_WITH(sim.reorder_storage(ids), Catch::Contains("twice"));
  ids.back() = 100000;
  CHECK_THROWS_WITH(sim.reorder_storage(ids), Catch::Contains("no particle 100000"));
  // A valid one moves the storage, not the particles.
  const Triple before = sim.position(17);
  sim.reorder_storage(storage_ids(sim.particle_ids(), Storage::reversed, 0));
  CHECK(sim.particles().id.front() == 699);
  CHECK(sim.position(17) == before);
}
