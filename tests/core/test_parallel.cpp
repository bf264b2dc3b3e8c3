// The multi-thread step gives the single thread's result bit for bit, also when
// the contacts gather in one part of the scene and the threads' shares of the
// pair contacts are moved to even out their work (Simulation::rebalance).
#include <omp.h>

#include <catch2/catch.hpp>
#include <cstring>

#include "box_walls.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
// 3D: first (lower indices, so the first half of the candidates) a cubic
// lattice of spheres 0.1 r apart, neighbours within the skin that never touch,
// high in a box; then an overlapping pile on its floor that is all contacts.
// Equal halves of the candidates are then very unequal work.
void uneven_box(Simulation<3>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  ParamValues law{{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "w", "linear", law);
  const double side = 0.012, r = 0.4e-3;
  test::add_box_walls(sim, side, 0.05, 1);
  const double spacing = 2.1 * r;
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b)
      for (int c = 0; c < 12; ++c) {
        ParticleSpec s;
        s.position = {0.001 + a * spacing, 0.001 + b * spacing, 0.035 + c * spacing};
        s.radius = r;
        s.material = 0;
        sim.add_particle(s);
      }
  FillSpec pile;
  pile.shape = RegionShape::box;
  pile.lo = {0, 0, 0}, pile.hi = {side, side, 0.006};
  pile.count = 900;
  pile.radius_min = r, pile.radius_max = r;
  pile.material = 0;
  pile.seed = 5;
  pile.allow_overlap = true;  // overlapping: contacts from the first step
  sim.fill(pile);
  sim.set_gravity({0, 0, -9.81});
}
}  // namespace

TEST_CASE("parallel: 3D, contacts gathered in one part: 1, 2 and 3 threads agree bit for bit",
          "[parallel]") {
  // The reactions on the walls too: summed over contacts that threads computed.
  std::vector<std::vector<double>> reactions(4);
  int corner_particles = 0;  // within the skin of two walls: wall contacts to split between threads
  int wall_candidates = 0;
  auto run = [&](int threads, GlobalStats* stats) {
    Simulation<3> sim;
    uneven_box(sim);
    sim.set_threads(threads);
    sim.set_parallel_thresholds(1024, 512);  // the parallel paths, on a small scene
    sim.advance(600);
    if (stats) *stats = sim.stats();
    for (const auto& w : sim.walls())
      reactions[threads].insert(reactions[threads].end(),
                                {w.force.x(), w.force.y(), w.force.z(), w.axial_torque});
    const auto& x = sim.particles().position;
    const auto& r = sim.particles().radius;
    corner_particles = wall_candidates = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      int near = 0;
      for (int axis = 0; axis < 2; ++axis)
        near += x[i][axis] - r[i] < sim.skin() || 0.012 - x[i][axis] - r[i] < sim.skin();
      near += x[i][2] - r[i] < sim.skin();
      corner_particles += near >= 2;
      wall_candidates += near;
    }
    return sim.flat_state();
  };
  GlobalStats two_stats, three_stats;
  auto one = run(1, nullptr), two = run(2, &two_stats), three = run(3, &three_stats);
  REQUIRE(two_stats.candidate_pairs >= 1024);  // the parallel contact loop ran
  // The wall loop ran on the threads (its threshold is an eighth of the
  // pairs'), and some particles had candidates with two walls.
  REQUIRE(wall_candidates > 128);
  REQUIRE(two_stats.contacts_wall > 10);
  REQUIRE(corner_particles > 10);
  CHECK(std::memcmp(reactions[1].data(), reactions[2].data(),
                    reactions[1].size() * sizeof(double)) == 0);
  CHECK(std::memcmp(reactions[1].data(), reactions[3].data(),
                    reactions[1].size() * sizeof(double)) == 0);
  CHECK(std::abs(reactions[1][2 * 4 + 2]) > 0);  // the floor (lo2) carries the pile
  INFO("contacts " << two_stats.contacts_particle << ", rebalances " << two_stats.thread_rebalances
                   << " and " << three_stats.thread_rebalances);
  REQUIRE(two_stats.contacts_particle > 50);
  // The shares started as equal halves of the candidates, most contacts in
  // one: they were moved (else this test would not test the moving).
  CHECK(two_stats.thread_rebalances > 0);
  CHECK(three_stats.thread_rebalances > 0);
  // The lists were rebuilt after the shares moved (the moved shares carry
  // over to the new lists, and the shared particles are marked afresh).
  INFO("list rebuilds " << two_stats.list_rebuilds);
  CHECK(two_stats.list_rebuilds > 2);
  for (const auto* other : {&two, &three}) {
    REQUIRE(one.id == other->id);
    CHECK(std::memcmp(one.position.data(), other->position.data(),
                      one.position.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(one.velocity.data(), other->velocity.data(),
                      one.velocity.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(one.spin.data(), other->spin.data(), one.spin.size() * sizeof(double)) == 0);
  }
}

TEST_CASE("parallel: a team smaller than asked for still gives the one-thread result",
          "[parallel]") {
  // OpenMP may give a region fewer threads than asked for. Here: a simulation
  // stepped inside another parallel region (nested regions get one thread),
  // and a 3-thread run, which the ctest entry parallel.thread_limit repeats
  // under OMP_THREAD_LIMIT=2 so that its regions get 2 of the 3 threads.
  auto run = [](int threads, bool nested) {
    Simulation<3> sim;
    uneven_box(sim);
    sim.set_threads(threads);
    sim.set_parallel_thresholds(1024, 512);
    if (nested) {
#pragma omp parallel num_threads(2)
      {
        if (omp_get_thread_num() == 0) sim.advance(200);
      }
    } else {
      sim.advance(200);
    }
    return sim.flat_state();
  };
  auto one = run(1, false);
  for (const bool nested : {true, false}) {
    INFO("nested " << nested << ", OMP_THREAD_LIMIT " << omp_get_thread_limit());
    auto squeezed = run(3, nested);
    REQUIRE(one.id == squeezed.id);
    CHECK(std::memcmp(one.position.data(), squeezed.position.data(),
                      one.position.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(one.velocity.data(), squeezed.velocity.data(),
                      one.velocity.size() * sizeof(double)) == 0);
  }
}

TEST_CASE("stage times: the wall contacts and the fixed-order sums are parts of the contact stage",
          "[parallel]") {
  for (const int threads : {1, 2}) {
    Simulation<3> sim;
    uneven_box(sim);
    sim.set_threads(threads);
    sim.set_parallel_thresholds(1024, 512);
    sim.advance(100);
    const auto& t = sim.stage_times();
    INFO("threads " << threads << ": force " << t.force << " s, walls " << t.walls << " s, scatter "
                    << t.scatter << " s");
    CHECK(t.walls > 0);
    CHECK(t.walls + t.scatter < t.force);
    if (threads == 1) CHECK(t.scatter == 0);    // one thread sums in slot order as it goes
    if (threads == 1) CHECK(t.pair_wait == 0);  // nobody to wait for
  }
}
