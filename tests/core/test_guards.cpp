// Guards on a run: overlaps deeper than overlap_warning are warned of once,
// with the speed their contact would launch the pair at; two particles passing
// through each other stop the run, naming them; a thread count far above the
// cores is warned of.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <thread>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double k = 2e4, r = 0.2e-3, density = 1200;
const double mass = 4.0 / 3.0 * M_PI * r * r * r * density;
const double omega = std::sqrt(k / (mass / 2));  // of the pair's spring, reduced mass m/2

template <int D>
void linear_pair_scene(Simulation<D>& sim, std::vector<std::string>& warnings) {
  sim.set_warning_handler([&warnings](const std::string& m) { warnings.push_back(m); });
  sim.add_material({"m", density, 0, 0, 0});
  sim.set_contact("m", "m", "linear", {{"k_normal", k}, {"restitution", 0.85}});
}
template <int D>
std::int64_t particle(Simulation<D>& sim, double x, double y, double vx) {
  ParticleSpec s;
  s.position = {x, y, 0};
  s.velocity = {vx, 0, 0};
  s.radius = r;
  s.material = 0;
  return sim.add_particle(s);
}
int count_containing(const std::vector<std::string>& list, const std::string& needle) {
  int n = 0;
  for (const auto& m : list) n += m.find(needle) != std::string::npos;
  return n;
}
// 40 particles of material 0 and one radius in `shape`, not overlapping (seed 3).
FillSpec forty_in(RegionShape shape, double particle_radius) {
  FillSpec fill;
  fill.shape = shape;
  fill.count = 40;
  fill.radius_min = fill.radius_max = particle_radius;
  fill.material = 0;
  fill.seed = 3;
  fill.allow_overlap = false;
  return fill;
}
}  // namespace

TEST_CASE("guards: an overlap above overlap_warning is warned of once, naming the pair",
          "[guards]") {
  for (double fraction : {0.05, 0.3}) {
    for (double threshold : {0.1, 0.5}) {
      Simulation<2> sim;
      std::vector<std::string> warnings;
      linear_pair_scene(sim, warnings);
      if (threshold != 0.1) sim.set_overlap_warning(threshold);
      // Two pairs at rest, far apart: one overlapping by `fraction` r, one by half of it.
      const double a = fraction * r;
      particle(sim, -(r - a / 2), 0, 0), particle(sim, r - a / 2, 0, 0);
      particle(sim, 0.01 - (r - a / 4), 0, 0), particle(sim, 0.01 + r - a / 4, 0, 0);
      sim.advance(200);
      INFO("overlap " << fraction << " r, overlap_warning " << threshold);
      const int warned = count_containing(warnings, "overlap by");
      if (fraction <= threshold) {
        CHECK(warned == 0);
        continue;
      }
      REQUIRE(warned == 1);  // once, although the overlap lasts several steps
      const std::string& w = warnings[0];
      CHECK_THAT(w, Catch::Contains("particles 0 and 1"));
      CHECK_THAT(w, Catch::Contains("step 0"));
      // The spring's energy (1/2) k a^2 given to the reduced mass: v = a omega.
      CHECK_THAT(w, Catch::Contains(fmt::format("at about {:.3g} m/s", a * omega)));
      // Started by the scene: the gentle start is offered.
      CHECK_THAT(w, Catch::Contains("overlap = false"));
    }
  }
}

TEST_CASE("guards: two particles passing through each other stop the run, naming them",
          "[guards]") {
  // Head-on at 10 r omega: the spring cannot stop them (its largest overlap would be
  // 10 r), and each step carries them 10 r omega dt ~ 0.8 r closer (dt = t_c / 40).
  const double v = 10 * r * omega;
  auto provoke = [&](auto& sim) {
    std::vector<std::string> warnings;
    linear_pair_scene(sim, warnings);
    particle(sim, -1.05 * r, 0, v / 2), particle(sim, 1.05 * r, 0, -v / 2);
    std::string message;
    try {
      sim.advance(100);
    } catch (const RunError& e) {
      message = e.what();
    }
    INFO("dimension " << sim.dimension() << ": " << message);
    CHECK_THAT(message, Catch::Contains("particles 0 and 1 pass through each other"));
    CHECK_THAT(message, Catch::Contains("closing at"));
    // The spring's energy at this depth is below that of the closing motion: a
    // shorter step would not help, and the message says so.
    CHECK_THAT(message, Catch::Contains("too soft for this impact"));
    CHECK_THAT(message, !Catch::Contains("reduce time_step"));
    // Stopped before the centres crossed: the output keeps a state that shows it.
    CHECK(sim.position(0)[0] < sim.position(1)[0]);
    CHECK(sim.step_count() < 10);
    // The deep overlap was first warned of, with no second warning.
    CHECK(count_containing(warnings, "overlap by") == 1);
  };
  Simulation<2> flat;
  provoke(flat);
  Simulation<3> solid;  // the batched 3D kernel keeps the deepest overlap too
  provoke(solid);
}

TEST_CASE("guards: a law too soft for an impact is named so, whatever energy is left at the stop",
          "[guards]") {
  // Head-on at 1.3 r omega: the spring would stop them 1.3 r deep; when the overlap
  // passes r it has taken 1 / 1.69 of the energy, and what is left (0.35 k r^2) is
  // below what it stores there (0.5 k r^2). Each step closes 0.1 r: the step
  // follows the approach, and only a stiffer law stops them (as at 4000 steps a
  // contact, where the same stop comes).
  for (double steps_per_contact : {40.0, 4000.0}) {
    Simulation<3> sim;
    std::vector<std::string> warnings;
    linear_pair_scene(sim, warnings);
    sim.set_contact("m", "m", "linear", {{"k_normal", k}, {"restitution", 1.0}});
    sim.set_steps_per_contact(steps_per_contact);
    const double v = 1.3 * r * omega;
    particle(sim, -1.001 * r, 0, v / 2), particle(sim, 1.001 * r, 0, -v / 2);
    std::string message;
    try {
      sim.advance(static_cast<std::int64_t>(steps_per_contact));
    } catch (const RunError& e) {
      message = e.what();
    }
    INFO(steps_per_contact << " steps a contact: " << message);
    CHECK_THAT(message, Catch::Contains("pass through each other"));
    CHECK_THAT(message, Catch::Contains("too soft for this impact"));
    CHECK_THAT(message, !Catch::Contains("reduce time_step"));
  }
}

TEST_CASE("guards: overlaps the scene made are pushed apart, not stopped", "[guards]") {
  // Coincident centres (overlap 2 r), then, after they separated, one particle moved
  // onto the other with set_position: neither is a pass-through.
  Simulation<3> sim;
  std::vector<std::string> warnings;
  linear_pair_scene(sim, warnings);
  particle(sim, 0, 0, 0), particle(sim, 0, 0, 0);
  REQUIRE_NOTHROW(sim.advance(2000));
  CHECK(sim.stats().contacts_particle == 0);
  const Triple far = sim.position(1);
  sim.set_position(0, {far[0] + 0.1 * r, far[1], far[2]});
  REQUIRE_NOTHROW(sim.advance(2000));
  CHECK(sim.stats().contacts_particle == 0);
  CHECK(count_containing(warnings, "overlap by") == 1);
}

TEST_CASE("guards: a setting changed mid-run does not make the steps' overlaps the scene's",
          "[guards]") {
  // A sphere pressed 0.3 r into a fixed one by gravity stays above overlap_warning. A
  // setting changed then (the skin: a whole prepare), or a particle added far from
  // every other (and the scene then saved and restarted, so that the grace must come
  // back for that particle alone), must not excuse what the steps do after it: two
  // spheres that then pass through each other still stop the run.
  for (const int change : {0, 1, 2, 3}) {
    const bool change_skin = change == 1, add_one = change >= 2, restart = change == 3;
    std::vector<std::string> warnings;
    const double depth = 0.3 * r;
    std::int64_t a = -1, b = -1;
    auto scene = [&](Simulation<3>& sim) {
      linear_pair_scene(sim, warnings);
      sim.set_gravity({0, -k * depth / mass, 0});  // k depth = m g: at rest 0.3 r deep
      ParticleSpec base;
      base.radius = r, base.material = 0, base.fixed = true;
      sim.add_particle(base);
      ParticleSpec resting = base;
      resting.fixed = false, resting.position = {0, 2 * r, 0};  // touching: no overlap yet
      sim.add_particle(resting);
      // Two free spheres far off, resting 0.3 r deep on a floor (a wall's overlap is not
      // a pair's).
      sim.add_material({"floor", 0, 0, 0, 0});
      sim.set_contact("m", "floor", "linear", {{"k_normal", k}, {"restitution", 0.85}});
      WallSpec floor;
      floor.name = "floor";
      floor.material = 1;
      floor.normal = {0, 1, 0};
      floor.point = {0, -r + depth, 0};
      sim.add_wall(floor);
      a = particle(sim, 0.01 - 2 * r, 0, 0), b = particle(sim, 0.01 + 2 * r, 0, 0);
    };
    auto sim = std::make_unique<Simulation<3>>();
    scene(*sim);
    sim->advance(3000);  // the resting sphere settles 0.3 r deep
    REQUIRE(count_containing(warnings, "overlap by") == 1);
    if (change_skin) sim->set_skin(0.6 * r);
    if (add_one) {
      ParticleSpec far;
      far.radius = r, far.material = 0, far.position = {0.05, 0.05, 0};
      sim->add_particle(far);
    }
    if (restart) {
      const StateBlob saved = sim->save_state();
      REQUIRE(saved.integers.count("guards.placed_ids") == 1);
      sim = std::make_unique<Simulation<3>>();
      scene(*sim);
      sim->load_state(saved);
    }
    const double v = 10 * r * omega;
    sim->set_velocity(a, {v / 2, 0, 0});
    sim->set_velocity(b, {-v / 2, 0, 0});
    std::string message;
    try {
      sim->advance(100);
    } catch (const RunError& e) {
      message = e.what();
    }
    INFO("skin changed: " << change_skin << ", a particle added: " << add_one
                          << ", restarted: " << restart << ": " << message);
    CHECK_THAT(message,
               Catch::Contains(fmt::format("particles {} and {} pass through each other", a, b)));
  }
}

TEST_CASE("guards: a checkpoint's placed ids are refused when damaged", "[guards]") {
  // The grace of particles placed mid-run names them (guards.placed_ids): ids out of
  // order, negative, or kept while the grace is off are refused by name.
  std::vector<std::string> warnings;
  auto scene = [&warnings](Simulation<3>& sim) {
    linear_pair_scene(sim, warnings);
    particle(sim, 0, 0, 0), particle(sim, 4 * r, 0, 0);
  };
  Simulation<3> sim;
  scene(sim);
  sim.advance(10);
  particle(sim, 8 * r, 0, 0);
  const StateBlob saved = sim.save_state();
  REQUIRE(saved.integers.at("guards.placed_ids") == std::vector<std::int64_t>{2});
  for (const auto& [ids, grace] : std::vector<std::pair<std::vector<std::int64_t>, std::int64_t>>{
           {{2, 1}, 1}, {{-1}, 1}, {{2}, 0}}) {
    StateBlob damaged = saved;
    damaged.integers["guards.placed_ids"] = ids;
    damaged.integers["guards"][0] = grace;
    Simulation<3> resumed;
    scene(resumed);
    CHECK_THROWS_WITH(resumed.load_state(damaged), Catch::Contains("'guards.placed_ids'"));
  }
  Simulation<3> resumed;
  scene(resumed);
  CHECK_NOTHROW(resumed.load_state(saved));
}

TEST_CASE("guards: placed ids are kept once each and in order, however they come", "[guards]") {
  // New particles (ids above all others) and older ones moved by set_position,
  // some twice, in mixed order: the checkpoint names each once, increasing.
  std::vector<std::string> warnings;
  Simulation<3> sim;
  linear_pair_scene(sim, warnings);
  for (int k = 0; k < 6; ++k) particle(sim, 4 * k * r, 0, 0);
  sim.advance(10);
  const std::int64_t added = particle(sim, 40 * r, 0, 0);
  sim.set_position(4, {16 * r, 0.5 * r, 0});
  sim.set_position(1, {4 * r, 0.5 * r, 0});
  sim.set_position(4, {16 * r, 0.25 * r, 0});
  sim.set_position(added, {40 * r, 0.5 * r, 0});
  const std::int64_t last = particle(sim, 60 * r, 0, 0);
  sim.set_position(3, {12 * r, 0.5 * r, 0});
  const StateBlob saved = sim.save_state();
  CHECK(saved.integers.at("guards.placed_ids") == std::vector<std::int64_t>{1, 3, 4, added, last});
  // Hundreds of moves alternating between two particles: the list is made unique
  // as it grows, and the checkpoint still names each once.
  for (int k = 0; k < 300; ++k) sim.set_position(k % 2 ? 2 : 5, {4 * (k % 2 ? 2 : 5) * r, 0, 0});
  CHECK(sim.save_state().integers.at("guards.placed_ids") ==
        std::vector<std::int64_t>{1, 2, 3, 4, 5, added, last});
}

TEST_CASE("guards: a particle pressed through a wall by a slow piston stops the run", "[guards]") {
  // A 1 mm sphere on a floor under a piston that comes down at 0.1 m/s (0.02 % of
  // the radius a step) onto a soft linear contact: it is squeezed to its centre. A
  // 20 mm plate as the floor (under a plane) would push it on through and out below
  // at 12 m/s; a 5 mm disk as the piston (over a half-space) would pass through it
  // and throw it out above. Either way the run stops while its centre is still
  // between the two, naming the particle and the thin wall.
  const double r = 1e-3;
  for (bool plate : {true, false}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"ball", 2500, 0, 0, 0});
    sim.add_material({"wall", 0, 0, 0, 0});
    const ParamValues law{{"k_normal", 1e4}, {"restitution", 0.3}, {"friction", 0.5}};
    sim.set_contact("ball", "ball", "linear", law);
    sim.set_contact("ball", "wall", "linear", law);
    ParticleSpec ball;
    ball.position = {0, r, 0}, ball.radius = r, ball.material = 0;
    const std::int64_t id = sim.add_particle(ball);
    WallSpec floor;
    floor.name = "floor", floor.material = 1, floor.normal = {0, 1, 0};
    if (plate) floor.bounded = true, floor.size_a = floor.size_b = 0.02;
    sim.add_wall(floor);
    WallSpec lid;
    lid.name = "lid", lid.material = 1, lid.velocity = {0, -0.1, 0};
    if (plate) {
      lid.normal = {0, -1, 0}, lid.point = {0, 2.1 * r, 0};
    } else {
      lid.type = WallType::disk, lid.center = {0, 2.1 * r, 0}, lid.normal = {0, 1, 0};
      lid.radius = 5 * r;
    }
    sim.add_wall(lid);
    sim.prepare();
    std::string message;
    try {
      sim.advance(static_cast<std::int64_t>(0.04 / sim.time_step()));
    } catch (const RunError& e) {
      message = e.what();
    }
    INFO("plate " << plate << ": " << message);
    CHECK_THAT(message, Catch::Contains(fmt::format("particle {} (radius", id)) &&
                            Catch::Contains(plate ? "is pressed through wall 'floor'"
                                                  : "is pressed through wall 'lid'") &&
                            Catch::Contains("too soft"));
    CHECK(sim.position(id)[1] > 0);
    CHECK(sim.position(id)[1] < 2.1 * r - 0.1 * sim.time());  // below the piston's face
  }
}

TEST_CASE("guards: overlap_warning outside 0 < w <= 1 is refused", "[guards]") {
  Simulation<2> sim;
  for (double bad : {0.0, -0.1, 1.5, std::nan("")})
    CHECK_THROWS_WITH(sim.set_overlap_warning(bad), Catch::Contains("overlap_warning must be"));
  CHECK_NOTHROW(sim.set_overlap_warning(1));
}

TEST_CASE("guards: a thread count far above the cores is warned of", "[guards]") {
  const unsigned cores = std::thread::hardware_concurrency();
  if (cores == 0) return;  // unknown: nothing to compare with
  Simulation<2> sim;
  std::vector<std::string> warnings;
  sim.set_warning_handler([&warnings](const std::string& m) { warnings.push_back(m); });
  sim.set_threads(static_cast<int>(cores));
  CHECK(warnings.empty());
  sim.set_threads(static_cast<int>(std::min(4096u, 4 * cores)));
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains(fmt::format("{} cores", cores)));
}

TEST_CASE("fill: small particles beside far larger ones are placed, none overlapping", "[guards]") {
  // Ten 1 mm spheres, then 30 of 10 um that may not overlap them: the occupied
  // space's grid has 20 um cells, which a 1 mm sphere would cover by 10^5 of
  // (and the fill would take minutes); such spheres have a grid of their own.
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
  for (int k = 0; k < 10; ++k) {
    ParticleSpec big;
    big.position = {2.5e-3 * k, 0, 0};
    big.radius = 1e-3;
    big.material = 0;
    sim.add_particle(big);
  }
  FillSpec fill;
  fill.shape = RegionShape::box;
  fill.lo = {-1e-3, -1e-3, -1e-3};
  fill.hi = {24e-3, 1e-3, 1e-3};
  fill.count = 30;
  fill.radius_min = fill.radius_max = 1e-5;
  fill.material = 0;
  fill.seed = 3;
  fill.allow_overlap = false;
  sim.fill(fill);
  REQUIRE(sim.particle_count() == 40);
  for (std::int64_t a = 10; a < 40; ++a)
    for (std::int64_t b = 0; b < 40; ++b) {
      if (a == b) continue;
      const Triple x = sim.position(a), y = sim.position(b);
      const double d = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
      CHECK(d >= sim.radius(a) + sim.radius(b));
    }
}

TEST_CASE("fill: a fill beside a bed keeps clear of the bed's particles within reach", "[guards]") {
  // Only the particles within reach of the fill's region are looked up: those
  // whose centres lie outside it by less than their radius plus the new one's
  // must still be kept clear of, on every side (a bed of large spheres around a
  // small box, in 3D, some fixed and some that may not be overlapped).
  for (const bool fixed : {true, false}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
    const double big = 1e-3, small = 2e-4;
    for (int a = -3; a <= 3; ++a)
      for (int b = -3; b <= 3; ++b)
        for (int c = -3; c <= 3; ++c) {
          if (std::abs(a) < 2 && std::abs(b) < 2 && std::abs(c) < 2) continue;  // the hole
          ParticleSpec s;
          s.position = {1.2 * big * a, 1.2 * big * b, 1.2 * big * c};
          s.radius = big, s.material = 0, s.fixed = fixed;
          sim.add_particle(s);
        }
    const std::int64_t bed = sim.particle_count();
    FillSpec fill;
    fill.shape = RegionShape::box;
    fill.lo = {-2.1 * big, -2.1 * big, -2.1 * big};
    fill.hi = {2.1 * big, 2.1 * big, 2.1 * big};
    fill.count = 40;
    fill.radius_min = fill.radius_max = small;
    fill.material = 0;
    fill.seed = 5;
    fill.allow_overlap = fixed;  // fixed ones are never overlapped; free ones here may not be
    sim.fill(fill);
    REQUIRE(sim.particle_count() == bed + 40);
    for (std::int64_t a = bed; a < bed + 40; ++a)
      for (std::int64_t b = 0; b < bed; ++b) {
        const Triple x = sim.position(a), y = sim.position(b);
        const double d = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
        CHECK(d >= sim.radius(a) + sim.radius(b));
      }
  }
}

TEST_CASE("fill: max_speed bounds every speed after the net momentum is taken off", "[guards]") {
  // Few particles of unequal sizes, in 2D and 3D over 20 seeds: taking the mean
  // velocity off alone gives speeds up to 1.7 max_speed here.
  auto check = [](auto& sim, int seed, int count) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
    FillSpec fill;
    fill.shape = RegionShape::box;
    fill.lo = {-0.05, -0.05, -0.05};
    fill.hi = {0.05, 0.05, 0.05};
    fill.count = count;
    fill.radius_min = 0.5e-3, fill.radius_max = 2e-3;
    fill.material = 0;
    fill.seed = seed;
    fill.max_speed = 1.0;
    sim.fill(fill);
    double fastest = 0;
    Triple momentum{};
    for (std::int64_t a = 0; a < count; ++a) {
      const Triple v = sim.velocity(a);
      fastest = std::max(fastest, std::hypot(v[0], v[1], v[2]));
      for (int k = 0; k < 3; ++k) momentum[k] += sim.mass(a) * v[k];
    }
    CHECK(fastest <= 1.0 + 1e-12);
    CHECK(fastest > 0);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(momentum[k]) < 1e-15);
  };
  for (int seed = 1; seed <= 20; ++seed)
    for (int count : {2, 3, 5}) {
      Simulation<2> flat;
      check(flat, seed, count);
      Simulation<3> solid;
      check(solid, seed, count);
    }
}

TEST_CASE("fill: along a periodic axis no particle overlaps one across the seam", "[guards]") {
  // A fixed sphere near the top of a 10 mm period reaches across the seam; a
  // fill that may not overlap, in a region beside the seam's other side, must
  // keep clear of it: a sphere too large for the fill's grid (1 mm beside
  // 0.05 mm) and one that fits in it (0.6 mm beside 0.2 mm).
  struct Case {
    double big, at, small, region_x;
    int count;
  };
  for (const Case c :
       {Case{1e-3, 9.6e-3, 0.05e-3, 1.5e-3, 300}, Case{0.6e-3, 9.8e-3, 0.2e-3, 3e-3, 100}}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
    const double period = 10e-3;
    sim.set_periodic(0, 0, period);
    ParticleSpec big;
    big.position = {c.at, 0, 0};
    big.radius = c.big;
    big.material = 0;
    big.fixed = true;
    sim.add_particle(big);
    FillSpec fill;
    fill.shape = RegionShape::box;
    fill.lo = {0, -1e-3, -1e-3};
    fill.hi = {c.region_x, 1e-3, 1e-3};
    fill.count = c.count;
    fill.radius_min = fill.radius_max = c.small;
    fill.material = 0;
    fill.seed = 5;
    fill.allow_overlap = false;
    sim.fill(fill);
    REQUIRE(sim.particle_count() == c.count + 1);
    int overlapping = 0;
    for (std::int64_t a = 1; a <= c.count; ++a) {
      const Triple x = sim.position(a), y = sim.position(0);
      double dx = x[0] - y[0];
      dx -= period * std::round(dx / period);  // the minimum image
      const double d = std::hypot(dx, x[1] - y[1], x[2] - y[2]);
      overlapping += d < sim.radius(a) + sim.radius(0);
    }
    INFO("fixed sphere of radius " << c.big << " m");
    CHECK(overlapping == 0);
  }
}

TEST_CASE("fill: a region over several periods places no two particles in each other", "[guards]") {
  // A rod 3 and 4 periods long along the periodic axis: each candidate is wrapped
  // into the box and checked against every particle's nearest image there (a
  // fixed sphere's too), and stored in the box as an added particle is.
  for (const int periods : {3, 4}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
    const double period = 10e-3, r = 0.5e-3;
    sim.set_periodic(0, 0, period);
    ParticleSpec fixed;
    fixed.position = {5e-3, 0, 0}, fixed.radius = 1e-3, fixed.material = 0, fixed.fixed = true;
    sim.add_particle(fixed);
    FillSpec fill;
    fill.shape = RegionShape::box;
    fill.lo = {-period, -0.6e-3, -0.6e-3};
    fill.hi = {(periods - 1) * period, 0.6e-3, 0.6e-3};
    fill.count = 4;
    fill.radius_min = fill.radius_max = r;
    fill.material = 0;
    fill.seed = 11;
    fill.allow_overlap = false;
    sim.fill(fill);
    REQUIRE(sim.particle_count() == 5);
    double deepest = 0;
    for (std::int64_t a = 0; a < 5; ++a) {
      INFO("particle " << a << " at x = " << sim.position(a)[0]);
      CHECK(sim.position(a)[0] >= 0);
      CHECK(sim.position(a)[0] <= period);
      for (std::int64_t b = a + 1; b < 5; ++b) {
        const Triple x = sim.position(a), y = sim.position(b);
        double dx = x[0] - y[0];
        dx -= period * std::round(dx / period);
        const double d = std::hypot(dx, x[1] - y[1], x[2] - y[2]);
        deepest = std::max(deepest, sim.radius(a) + sim.radius(b) - d);
      }
    }
    INFO(periods << " periods");
    CHECK(deepest <= 0);
  }
}

// set_position holds a moved particle to what an added one is held to: inside
// the periodic box (one period from its image, where the force loops look),
// inside every wall. It used to place it anywhere: a particle moved 1.5
// periods out missed its contact for a step; one moved outside a drum was
// shot back in by the wall.
TEST_CASE(
    "guards: set_position and add_particle wrap into the periodic box, a place outside a wall is "
    "refused",
    "[guards]") {
  std::vector<std::string> warnings;
  {
    Simulation<3> sim;
    linear_pair_scene(sim, warnings);
    const double period = 20 * r;
    sim.set_periodic(0, 0, period);
    const std::int64_t a = particle(sim, 0.5 * r, 0, 0);
    const std::int64_t b = particle(sim, 10 * r, 0, 0);
    sim.prepare();
    sim.advance(1);
    CHECK(sim.stats().contacts_particle == 0);
    // 1.9 r from a, two periods out: overlapping a.
    sim.set_position(b, {0.5 * r + 1.9 * r + 2 * period, 0, 0});
    CHECK(sim.position(b)[0] == Approx(2.4 * r).epsilon(1e-12));
    // So is an added particle, at once (not only when the next run prepares).
    const std::int64_t c = particle(sim, 10 * r - 3 * period, 0, 0);
    CHECK(sim.position(c)[0] == Approx(10 * r).epsilon(1e-12));
    const std::int64_t d = particle(sim, -5 * r, 0, 0);
    CHECK(sim.position(d)[0] == Approx(15 * r).epsilon(1e-12));
    sim.remove_particle(c);
    sim.remove_particle(d);
    sim.advance(1);
    CHECK(sim.stats().contacts_particle == 1);
    CHECK(sim.force(a)[0] < 0);  // b, on a's +x side, pushes a to -x
    // So far out that the wrap would lose the place to round-off: refused, the
    // particle kept where it was.
    const Triple before = sim.position(b);
    CHECK_THROWS_WITH(sim.set_position(b, {1e30, 0, 0}), Catch::Contains("million periods"));
    CHECK(sim.position(b) == before);
    CHECK_THROWS_WITH(particle(sim, -1e16, 0, 0), Catch::Contains("million periods"));
  }
  {
    Simulation<2> sim;
    linear_pair_scene(sim, warnings);
    WallSpec drum;
    drum.name = "drum";
    drum.type = WallType::cylinder;
    drum.material = 0;
    drum.radius = 10 * r;
    sim.add_wall(drum);
    const std::int64_t a = particle(sim, 0, 0, 0);
    sim.prepare();
    CHECK_THROWS_WITH(sim.set_position(a, {10.5 * r, 0, 0}),
                      Catch::Contains("would lie outside wall 'drum'"));
    CHECK(sim.position(a)[0] == 0.0);  // left where it was
    warnings.clear();
    sim.set_position(a, {9.5 * r, 0, 0});
    CHECK(count_containing(warnings, "overlaps wall 'drum'") == 1);
  }
}

// A step that fails a check after the particles moved (one moving farther than
// the smallest radius) leaves the clock with them: the failure's snapshot, and a
// scene that catches the error and goes on, see positions and time that belong
// together.
TEST_CASE("guards: a failing step leaves positions and time together", "[guards]") {
  Simulation<3> sim;
  std::vector<std::string> warnings;
  linear_pair_scene(sim, warnings);
  const double dt = 1e-6, speed = 400;  // 0.4 mm a step, twice the radius
  sim.set_time_step(dt);
  particle(sim, 0, 0, speed);
  double time_seen = -1, x_seen = 0;
  sim.set_failure_handler([&](const std::string&) {
    time_seen = sim.time();
    x_seen = sim.position(0)[0];
  });
  CHECK_THROWS_WITH(sim.advance(3), Catch::Contains("more than the smallest radius"));
  CHECK(sim.step_count() == 1);
  CHECK(sim.time() == Approx(dt));
  CHECK(time_seen == Approx(dt));
  CHECK(x_seen == Approx(speed * dt));
  CHECK(sim.position(0)[0] == Approx(speed * sim.time()));
}

TEST_CASE("guards: a Hertzian contact pressed deeper than the step resolves is warned of once",
          "[guards]") {
  // Two soft spheres (E = 1 MPa, r = 1 mm, rho = 1000) pressed 5 % of a radius:
  // the no-slip tangential spring's omega = sqrt(3.5 x 8 G* a / m*) = 1.55e4 1/s,
  // so omega dt = 0.54 at the default n = 40 (no warning) and 1.07 at n = 20.
  for (const double n : {40.0, 20.0}) {
    std::vector<std::string> warnings;
    Simulation<3> sim;
    sim.set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
    sim.add_material({"soft", 1000, 1e6, 0.3, 0});
    sim.set_contact("soft", "soft", "hertz_mindlin", {{"restitution", 0.5}, {"friction", 0.5}});
    sim.set_steps_per_contact(n);
    ParticleSpec a, b;
    a.radius = b.radius = 1e-3, a.material = b.material = 0;
    a.fixed = true;
    b.position = {0, 0, 1.95e-3};
    sim.add_particle(a);
    sim.add_particle(b);
    sim.advance(5);
    int deep = 0;
    for (const auto& w : warnings) deep += w.find("stiffest mode") != std::string::npos;
    INFO("n = " << n << "; warnings: " << fmt::format("{}", fmt::join(warnings, " | ")));
    if (n == 40) {
      CHECK(deep == 0);
    } else {
      REQUIRE(deep == 1);
      for (const auto& w : warnings)
        if (w.find("stiffest mode") != std::string::npos) {
          CHECK_THAT(w, Catch::Contains("soft-soft (hertz_mindlin, particle-particle)") &&
                            Catch::Contains("omega dt = 1.07") &&
                            Catch::Contains("raise steps_per_contact to 30"));
        }
    }
  }
}

TEST_CASE("guards: a deep contact is judged by its own law, not by a stiffer law's that is apart",
          "[guards]") {
  // Soft spheres (E = 1 MPa) pressed 30 % of a radius beside stiff ones (E = 200
  // GPa) of the same law: the stiff pair sets the step, sqrt(2e5) = 450 times
  // shorter than the soft pair's own (the Rayleigh time goes as 1 / sqrt(E)), so
  // the soft contact's mode has omega dt ~ 0.002. At the same depth the stiff
  // pair's mode is past the bound (omega dt ~ 0.85 at n = 40, as depth^(1/4)
  // from 0.54 at 5 %): warned only once the stiff spheres are themselves
  // pressed that deep.
  for (const bool stiff_pressed : {false, true}) {
    std::vector<std::string> warnings;
    Simulation<3> sim;
    sim.set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
    sim.add_material({"soft", 1000, 1e6, 0.3, 0});
    sim.add_material({"stiff", 1000, 2e11, 0.3, 0});
    const ParamValues law{{"restitution", 0.5}, {"friction", 0.5}};
    for (const char* a : {"soft", "stiff"})
      for (const char* b : {"soft", "stiff"}) sim.set_contact(a, b, "hertz_mindlin", law);
    auto add = [&](int material, double x, double z, bool fixed) {
      ParticleSpec s;
      s.radius = 1e-3, s.material = material, s.fixed = fixed, s.position = {x, 0, z};
      sim.add_particle(s);
    };
    add(0, 0, 0, true);
    add(0, 0, 1.7e-3, false);  // 30 % of a radius deep
    add(1, 0.1, 0, true);
    add(1, 0.1, stiff_pressed ? 1.7e-3 : 3e-3, false);  // 30 % deep, or apart
    sim.advance(3);
    int deep = 0;
    for (const auto& w : warnings) deep += w.find("stiffest mode") != std::string::npos;
    INFO("stiff pair pressed: " << stiff_pressed
                                << "; warnings: " << fmt::format("{}", fmt::join(warnings, " | ")));
    if (!stiff_pressed) {
      CHECK(deep == 0);
    } else {
      REQUIRE(deep == 1);
      for (const auto& w : warnings)
        if (w.find("stiffest mode") != std::string::npos)
          CHECK_THAT(w, Catch::Contains("stiff-stiff (hertz_mindlin, particle-particle)"));
    }
  }
}

TEST_CASE(
    "guards: a particle pressed deep into a half-space is warned of, and stopped a radius "
    "past it at once",
    "[guards]") {
  // A 1 mm sphere between a floor and a lid, both half-spaces, the lid coming
  // down at 0.01 m/s onto a soft linear contact: warned once when the contact is
  // deeper than overlap_warning (10 % of the radius), and stopped within a step
  // of its centre passing a radius beyond a wall (overlap 2 r), although the
  // particle, squeezed still, never triggers a list rebuild.
  const double r = 1e-3, speed = 0.01;
  std::vector<std::string> warnings;
  Simulation<3> sim;
  sim.set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
  sim.add_material({"ball", 2500, 0, 0, 0});
  sim.add_material({"wall", 0, 0, 0, 0});
  const ParamValues law{{"k_normal", 10}, {"restitution", 0.3}, {"friction", 0.5}};
  sim.set_contact("ball", "ball", "linear", law);
  sim.set_contact("ball", "wall", "linear", law);
  ParticleSpec ball;
  ball.position = {0, r, 0}, ball.radius = r, ball.material = 0;
  const std::int64_t id = sim.add_particle(ball);
  WallSpec floor;
  floor.name = "floor", floor.material = 1, floor.normal = {0, 1, 0};
  sim.add_wall(floor);
  WallSpec lid;
  lid.name = "lid", lid.material = 1, lid.velocity = {0, -speed, 0};
  lid.normal = {0, -1, 0}, lid.point = {0, 2 * r, 0};
  sim.add_wall(lid);
  sim.prepare();
  std::string message;
  try {
    sim.advance(static_cast<std::int64_t>(0.5 / sim.time_step()));
  } catch (const RunError& e) {
    message = e.what();
  }
  INFO(message << "; warnings: " << fmt::format("{}", fmt::join(warnings, " | ")));
  CHECK(count_containing(warnings, fmt::format("particle {} (radius 0.001 m) is pressed", id)) ==
        1);
  CHECK_THAT(message, Catch::Contains(fmt::format("particle {} (radius", id)) &&
                          Catch::Contains("escaped through wall"));
  // The two walls' overlaps, equal, sum to speed t: the centre is a radius past
  // both (an overlap of 2 r) at t = 4 r / speed, give or take a step.
  CHECK(sim.time() == Approx(4 * r / speed).epsilon(1e-3));
}

TEST_CASE("guards: a sphere driven through a post thinner than itself stops the run", "[guards]") {
  // A 1 mm sphere thrown at 1 m/s at an outside cylinder of radius 0.3 mm with a
  // contact far too soft for it (k = 1 N/m): its centre can never be a radius
  // past the post's surface, and past the axis the post would push it on
  // through. The run stops once the centre is within half the post's radius of
  // the axis; a post of 5 mm stops it a radius past its surface, as a plane.
  const double r = 1e-3;
  for (const double post_radius : {0.3e-3, 5e-3}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"ball", 2500, 0, 0, 0});
    sim.add_material({"wall", 0, 0, 0, 0});
    const ParamValues law{{"k_normal", 1}, {"restitution", 0.9}, {"friction", 0.0}};
    sim.set_contact("ball", "wall", "linear", law);
    WallSpec post;
    post.name = "post", post.type = WallType::cylinder, post.material = 1, post.inside = false;
    post.radius = post_radius, post.axis = {0, 0, 1};
    sim.add_wall(post);
    ParticleSpec ball;
    ball.position = {-(post_radius + 2 * r), 0, 0}, ball.velocity = {1, 0, 0};
    ball.radius = r, ball.material = 0;
    const std::int64_t id = sim.add_particle(ball);
    sim.prepare();
    std::string message;
    try {
      sim.advance(static_cast<std::int64_t>(0.02 / sim.time_step()));
    } catch (const RunError& e) {
      message = e.what();
    }
    INFO("post radius " << post_radius << ": " << message);
    CHECK_THAT(message, Catch::Contains("escaped through wall 'post'"));
    // Stopped on the step the centre came that deep (a step is 0.25 mm here).
    const double x = sim.position(id)[0], step = 1.0 * sim.time_step() * 1.01;
    if (post_radius < r) {
      CHECK(std::abs(x) < 0.5 * post_radius);
    } else {
      CHECK(x > -(post_radius - r));
      CHECK(x < -(post_radius - r) + step);
    }
  }
}

TEST_CASE("guards: in a periodic scene the central field pulls towards the line along the axis",
          "[guards]") {
  // Periodic along z over 10 mm, the field's point at the origin: a particle near
  // the seam (z = 9.9 mm, 0.2 mm from its image below z = 0) must not be pulled
  // across the box, nor one at z = 0.1 mm the other way; both are pulled to the axis.
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 0.5}});
  sim.set_periodic(2, 0, 10e-3);
  for (const double z : {9.9e-3, 0.1e-3}) {
    ParticleSpec s;
    s.position = {z > 5e-3 ? 2e-3 : -2e-3, 0, z}, s.radius = 0.5e-3, s.material = 0;
    sim.add_particle(s);
  }
  sim.set_central_field({0, 0, 0}, 100);
  sim.set_time_step(1e-5);
  sim.advance(10);
  for (std::int64_t id : {0, 1}) {
    INFO("particle " << id);
    CHECK(sim.velocity(id)[2] == 0);
    CHECK(sim.velocity(id)[0] == Approx((id == 0 ? -1 : 1) * 100 * 10 * 1e-5).epsilon(1e-9));
  }
}

TEST_CASE("fill: a fill on both sides of a cone is warned of, one inside it is not", "[guards]") {
  // A hopper (radius 5 mm at the bottom to 30 mm at the top over 30 mm): a cone is
  // touched on both sides, so only the region bounds a fill around it.
  for (const double region_radius : {30e-3, 4e-3}) {
    std::vector<std::string> warnings;
    Simulation<3> sim;
    linear_pair_scene(sim, warnings);
    WallSpec cone;
    cone.name = "hopper", cone.type = WallType::cone, cone.material = 0;
    cone.axis = {0, 0, 1}, cone.z_lo = 0, cone.z_hi = 30e-3;
    cone.radius_lo = 5e-3, cone.radius_hi = 30e-3;
    sim.add_wall(cone);
    FillSpec fill = forty_in(RegionShape::cylinder, 1e-3);
    fill.radius = region_radius, fill.z_min = 2e-3, fill.z_max = 28e-3;
    sim.fill(fill);
    const int said = count_containing(warnings, "outside cone 'hopper'");
    INFO("region radius " << region_radius);
    CHECK(said == (region_radius > 20e-3 ? 1 : 0));
  }
}

TEST_CASE("fill: a fill on both sides of a closed polyline that is not solid is warned of",
          "[guards]") {
  // A 2D container drawn as a closed polyline: touched on both sides, it has no
  // inside, so only the region bounds a fill around it. Solid, it is a body and
  // the fill places nothing inside (no warning).
  struct Case {
    double region_radius;
    bool solid;
    int expected;
  };
  for (const Case c : {Case{20e-3, false, 1}, Case{4e-3, false, 0}, Case{20e-3, true, 0}}) {
    std::vector<std::string> warnings;
    Simulation<2> sim;
    linear_pair_scene(sim, warnings);
    PolylineWallSpec box;
    box.name = "box", box.material = 0, box.closed = true, box.solid = c.solid;
    box.points = {{-5e-3, -5e-3}, {5e-3, -5e-3}, {5e-3, 5e-3}, {-5e-3, 5e-3}};
    sim.add_polyline_wall(box);
    FillSpec fill = forty_in(RegionShape::ball, 3e-4);
    fill.radius = c.region_radius;
    sim.fill(fill);
    const int said = count_containing(warnings, "outside closed polyline 'box'");
    INFO("region radius " << c.region_radius << ", solid " << c.solid);
    CHECK(said == c.expected);
  }
}

TEST_CASE("guards: particles far enough from the origin to round their overlaps are warned of once",
          "[guards]") {
  // r = 0.2 mm: positions rounded to 1e-7 r from about 4.5e8 r out (9e4 m).
  for (double offset : {1e3, 1e6}) {
    Simulation<2> sim;
    std::vector<std::string> warnings;
    linear_pair_scene(sim, warnings);
    particle(sim, offset - r, offset, 0), particle(sim, offset + r, offset, 0);
    sim.advance(10);
    sim.advance(10);
    INFO("offset " << offset << " m");
    CHECK(count_containing(warnings, "from the origin") == (offset > 1e5 ? 1 : 0));
    if (offset > 1e5) CHECK_THAT(warnings[0], Catch::Contains("5e+09 times the smallest radius"));
  }
}
