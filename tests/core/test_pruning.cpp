// Pruned pair lists (Simulation::set_pruning) change which candidates the
// contact loop's listing pass looks at, never what it finds: runs with and
// without them agree bit for bit. The scenes are granular gases in closed
// boxes, under gravity, so contacts keep forming between particles that were
// far apart (beyond the prune distance) when the lists were last pruned, and
// the lists are pruned again and again between rebuilds.
#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "box_walls.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
// A gas of `count` spheres (discs in 2D) with random velocities up to 1 m/s.
template <int D>
void gas(Simulation<D>& sim, const std::string& model, int count) {
  sim.set_warning_handler([](const std::string&) {});
  const bool adhesive = model == "thornton_jkr";
  sim.add_material({"p", 2500, 1e7, 0.3, adhesive ? 0.5 : 0.0});
  sim.add_material({"w", 0, 1e7, 0.3, 0});
  ParamValues law{{"friction", 0.3}};  // Thornton's laws: the materials' elasticity
  if (model == "linear") law = {{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
  if (model == "walton_braun") law = {{"k_load", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
  sim.set_contact("p", "p", model, law);
  sim.set_contact("p", "w", model, law);
  const double side = D == 3 ? 0.008 : 0.02;
  test::add_box_walls(sim, side, side, 1);
  FillSpec fill;
  fill.shape = RegionShape::box;
  fill.lo = {0, 0, 0};
  fill.hi = {side, side, D == 3 ? side : 0.0};
  fill.count = count;
  fill.radius_min = 0.2e-3, fill.radius_max = 0.3e-3;
  fill.material = 0;
  fill.seed = 11;
  fill.max_speed = adhesive ? 0.05 : 1.0;  // slow enough for sticking
  fill.allow_overlap = false;
  sim.fill(fill);
  sim.set_gravity({0, D == 3 ? 0.0 : -9.81, D == 3 ? -9.81 : 0.0});
  // Adhesive: the smallest skin the engine allows (twice the distance a JKR
  // contact holds on to), so contacts stretch past the prune distance (a
  // quarter of the skin) and the pruned lists keep them because they are in
  // contact, not because they are near.
  if (adhesive) sim.set_skin(5e-6);  // above 1.5 x 2.18e-6 m, that distance here
}

struct Outcome {
  SimulationBase::FlatState state;
  GlobalStats stats;
  std::int64_t fewest_visited = -1;  // the fewest pair candidates a step looked at
};

template <int D>
// toggled: pruning switched off for a stretch in the middle of the run (the
// lists noted before must not be trusted after it).
Outcome run(const std::string& model, int count, int threads, bool pruning, int steps,
            bool toggled = false) {
  Simulation<D> sim;
  gas(sim, model, count);
  sim.set_threads(threads);
  sim.set_parallel_thresholds(256, 256);  // the parallel paths, on a small scene
  sim.set_pruning(pruning);
  Outcome out;
  for (int s = 0; s < steps; s += 10) {
    if (toggled) sim.set_pruning((s / 10) % 7 < 3);  // off 40 steps of every 70
    sim.advance(10);
    const GlobalStats g = sim.stats();
    if (out.fewest_visited < 0 || g.pair_candidates_visited < out.fewest_visited)
      out.fewest_visited = g.pair_candidates_visited;
  }
  out.state = sim.flat_state();
  out.stats = sim.stats();
  return out;
}

void check_same(const Outcome& a, const Outcome& b) {
  REQUIRE(a.state.id == b.state.id);
  CHECK(std::memcmp(a.state.position.data(), b.state.position.data(),
                    a.state.position.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(a.state.velocity.data(), b.state.velocity.data(),
                    a.state.velocity.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(a.state.spin.data(), b.state.spin.data(),
                    a.state.spin.size() * sizeof(double)) == 0);
  CHECK(a.stats.contacts_particle == b.stats.contacts_particle);
}

template <int D>
void compare(const std::string& model, int count, int steps) {
  for (const int threads : {1, 2}) {
    INFO(D << "D, " << model << ", " << threads << " thread(s)");
    const Outcome full = run<D>(model, count, threads, false, steps);
    const Outcome pruned = run<D>(model, count, threads, true, steps);
    INFO("rebuilds " << pruned.stats.list_rebuilds << ", prunes " << pruned.stats.pair_list_prunes
                     << ", candidates " << pruned.stats.candidate_pairs << ", fewest visited "
                     << pruned.fewest_visited);
    // The scene does what the test needs: contacts, lists rebuilt, and more
    // prunes than rebuilds (pruned again between rebuilds, as particles moved).
    REQUIRE(full.stats.contacts_particle > 20);
    REQUIRE(pruned.stats.list_rebuilds >= 2);
    REQUIRE(pruned.stats.pair_list_prunes > pruned.stats.list_rebuilds);
    // Without pruning every step looks at every pair candidate; with it, some
    // steps look at fewer (the pruned lists were in use).
    CHECK(full.stats.pair_list_prunes == 0);
    CHECK(full.fewest_visited > 0);
    CHECK(pruned.fewest_visited < full.fewest_visited);
    check_same(full, pruned);
    const Outcome toggled = run<D>(model, count, threads, true, steps, true);
    check_same(full, toggled);
  }
}
}  // namespace

TEST_CASE("pruning: 3D linear gas, the same bit for bit with and without pruned lists",
          "[pruning]") {
  compare<3>("linear", 2000, 3000);
}

TEST_CASE("pruning: 3D adhesive (JKR) gas, the same bit for bit with and without pruned lists",
          "[pruning]") {
  compare<3>("thornton_jkr", 2000, 3000);
}

TEST_CASE("pruning: 2D Walton-Braun gas, the same bit for bit with and without pruned lists",
          "[pruning]") {
  compare<2>("walton_braun", 900, 3000);
}

TEST_CASE("pruning: an adhesive contact stretched past the prune distance stays in the lists",
          "[pruning]") {
  // Pairs of JKR spheres pulled apart at different speeds: each contact holds
  // on until the surfaces are ~2.2 um apart, past the prune distance (a
  // quarter of the 5 um skin). The pruned lists keep such a contact because it
  // is in contact, not because it is near; were it dropped at a prune, its
  // force would vanish and its spheres would part sooner.
  const double r = 0.25e-3, skin = 5e-6;
  bool visited_fewer = false;
  auto run = [&](bool pruning, int* stretched_prunes) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 1e7, 0.3, 0.5});
    sim.set_contact("p", "p", "thornton_jkr", {{"friction", 0.3}});
    sim.set_skin(skin);
    // A step well below the rule's (4.3e-6 s here), so that the spheres move
    // little per step and the lists live several steps between prunes.
    sim.set_time_step(2e-7);
    constexpr int pairs = 8;
    for (int k = 0; k < pairs; ++k)
      for (const double side : {-1.0, 1.0}) {
        ParticleSpec s;
        s.position = {side * (r - 0.2e-6), k * 4 * r, 0};  // overlapping by 0.4 um
        s.velocity = {side * (0.05 + 0.02 * k), 0, 0};
        s.radius = r;
        s.material = 0;
        sim.add_particle(s);
      }
    // Resting spheres 3 um apart: candidates (within the skin) that the
    // pruned lists leave out, so that the lists are short enough to be used.
    for (int k = 0; k < 40; ++k) {
      ParticleSpec s;
      s.position = {0, -4 * r, k * (2 * r + 3e-6)};
      s.radius = r;
      s.material = 0;
      sim.add_particle(s);
    }
    sim.set_pruning(pruning);
    for (int s = 0; s < 3000; ++s) {
      // A contact stretched past the prune distance now, and the lists pruned this step?
      bool stretched = false;
      const auto& x = sim.particles().position;
      for (int k = 0; k < pairs; ++k)
        stretched |= (x[2 * k + 1] - x[2 * k]).norm() - 2 * r > 0.25 * skin;
      const auto prunes = sim.stats().pair_list_prunes;
      sim.advance(1);
      if (stretched && sim.stats().contacts_particle > 0 && sim.stats().pair_list_prunes > prunes)
        ++*stretched_prunes;
      // The pruned lists were in use (fewer candidates looked at than there are).
      if (sim.stats().pair_candidates_visited < sim.stats().candidate_pairs) visited_fewer = true;
    }
    return sim.flat_state();
  };
  int unused = 0, stretched_prunes = 0;
  const auto full = run(false, &unused);
  const auto pruned = run(true, &stretched_prunes);
  // The lists were pruned while some contact was stretched past the distance.
  REQUIRE(stretched_prunes > 0);
  REQUIRE(visited_fewer);
  CHECK(std::memcmp(full.position.data(), pruned.position.data(),
                    full.position.size() * sizeof(double)) == 0);
  CHECK(std::memcmp(full.velocity.data(), pruned.velocity.data(),
                    full.velocity.size() * sizeof(double)) == 0);
}

TEST_CASE("pruning: notes forced by another rank's schedule change nothing but the notes",
          "[pruning]") {
  // DistributedRun has every rank note its pruned lists when any rank's
  // schedule calls for it (Simulation::note_pruned_lists_with), so that no
  // rank waits at the next forward for another's noting step. A forced note
  // must note (the prune count grows by it) and must not change a bit.
  auto run = [](int force_every, std::int64_t* prunes) {
    Simulation<2> sim;
    gas(sim, "walton_braun", 900);
    sim.set_pruning(true);
    for (int s = 1; s <= 1500; ++s) {
      if (force_every > 0 && s % force_every == 0) sim.note_pruned_lists_with(true);
      sim.advance(1);
    }
    *prunes = sim.stats().pair_list_prunes;
    return sim.flat_state();
  };
  std::int64_t own = 0, every_step = 0, every_third = 0;
  const auto plain = run(0, &own);
  const auto forced = run(1, &every_step);
  const auto some = run(3, &every_third);
  // Its own schedule notes far less often than every step; forced at every
  // step, every step notes; forced at every third, at least those do.
  REQUIRE(own > 1);
  CHECK(own < 500);
  CHECK(every_step == 1500);
  CHECK(every_third >= 500);
  CHECK(every_third < every_step);
  for (const auto* other : {&forced, &some}) {
    CHECK(std::memcmp(plain.position.data(), other->position.data(),
                      plain.position.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(plain.velocity.data(), other->velocity.data(),
                      plain.velocity.size() * sizeof(double)) == 0);
  }
}
