// Simulation::set_fixed: a particle fixed mid-run stays where it is, at rest,
// holds what rests on it and leaves the walls; freed, it moves from rest with
// its own mass; the time-step rule and the free mass follow.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "contact/parallel_bond.hpp"
#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double r = 1e-3, density = 2500, g = 9.81;
const double mass = 4.0 / 3.0 * M_PI * r * r * r * density;

// Two spheres stacked on a floor (linear law, strongly damped), settled.
struct Stack {
  Simulation<3> sim;
  std::int64_t bottom = -1, top = -1;
  int floor = -1;
  Stack() {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"glass", density, 0, 0, 0});
    sim.add_material({"steel", 0, 0, 0, 0});
    for (const char* other : {"glass", "steel"})
      sim.set_contact("glass", other, "linear", {{"k_normal", 1e4}, {"restitution", 0.2}});
    sim.set_gravity({0, 0, -g});
    WallSpec w;
    w.name = "floor", w.material = 1, w.normal = {0, 0, 1};
    floor = sim.add_wall(w);
    ParticleSpec s;
    s.radius = r, s.material = 0, s.position = {0, 0, r};
    bottom = sim.add_particle(s);
    s.position = {0, 0, 3 * r};
    top = sim.add_particle(s);
    sim.advance(40000);
  }
};
}  // namespace

TEST_CASE("set_fixed: a particle fixed mid-run holds what rests on it and leaves the floor",
          "[set_fixed]") {
  Stack stack;
  Simulation<3>& sim = stack.sim;
  REQUIRE(sim.wall_force(stack.floor)[2] == Approx(-2 * mass * g).epsilon(1e-3));
  REQUIRE(sim.stats().free_mass == Approx(2 * mass).epsilon(1e-12));
  sim.set_fixed(stack.bottom, true);
  CHECK(sim.stats().free_mass == Approx(mass).epsilon(1e-12));
  const Triple bottom_at = sim.position(stack.bottom), top_at = sim.position(stack.top);
  sim.advance(20000);
  // The fixed sphere does not move and touches no wall; the top one still rests on it.
  CHECK(sim.position(stack.bottom) == bottom_at);
  CHECK(sim.velocity(stack.bottom) == Triple{0, 0, 0});
  CHECK(sim.wall_force(stack.floor)[2] == 0);
  CHECK(std::abs(sim.position(stack.top)[2] - top_at[2]) < 1e-3 * r);
  CHECK(sim.stats().contacts_particle == 1);

  // Freed, it falls back the little its floor contact was pressed, from rest, and
  // the floor carries both again.
  sim.set_fixed(stack.bottom, false);
  CHECK(sim.velocity(stack.bottom) == Triple{0, 0, 0});
  CHECK(sim.stats().free_mass == Approx(2 * mass).epsilon(1e-12));
  sim.advance(40000);
  CHECK(sim.wall_force(stack.floor)[2] == Approx(-2 * mass * g).epsilon(1e-3));
  // Freeing a free particle changes nothing (a moving one keeps its velocity),
  // nor does fixing a fixed one; two fixed particles hold no contact.
  sim.set_velocity(stack.top, {0.01, 0, 0});
  sim.set_fixed(stack.top, false);
  CHECK(sim.velocity(stack.top) == Triple{0.01, 0, 0});
  sim.set_fixed(stack.bottom, true);
  sim.set_fixed(stack.top, true);
  sim.set_fixed(stack.top, true);
  CHECK(sim.stats().free_mass == 0);
  sim.advance(10);
  CHECK(sim.stats().contacts_particle == 0);
  CHECK(sim.stats().contacts_wall == 0);
}

TEST_CASE("set_fixed: a particle freed where it overlaps another is pushed out, not stopped",
          "[set_fixed]") {
  // Two fixed spheres overlapping by 1.1 r (a pair of fixed particles is never a
  // contact): freed, the overlap is the scene's, as an added particle's, and is
  // pushed apart rather than taken for a pass-through.
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.set_contact("glass", "glass", "linear", {{"k_normal", 1e2}, {"restitution", 0.5}});
  ParticleSpec s;
  s.radius = r, s.material = 0, s.fixed = true;
  sim.add_particle(s);
  s.position = {0.9 * r, 0, 0};
  const std::int64_t second = sim.add_particle(s);
  s.position = {0.1, 0, 0}, s.fixed = false;
  sim.add_particle(s);  // a free one far away
  sim.advance(100);
  sim.set_fixed(second, false);
  REQUIRE_NOTHROW(sim.advance(20000));
  CHECK(sim.position(second)[0] > 2 * r);
}

TEST_CASE("set_fixed: a fixed particle a moving wall has passed cannot be freed", "[set_fixed]") {
  // A floor rising past a fixed sphere (a fixed particle touches no wall): freed
  // there it would lie outside the wall, which is refused, and it stays fixed.
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.add_material({"steel", 0, 0, 0, 0});
  for (const char* other : {"glass", "steel"})
    sim.set_contact("glass", other, "linear", {{"k_normal", 1e4}, {"restitution", 0.5}});
  WallSpec floor;
  floor.name = "floor", floor.material = 1, floor.normal = {0, 0, 1};
  floor.velocity = {0, 0, 1};
  sim.add_wall(floor);
  ParticleSpec s;
  s.radius = r, s.material = 0, s.fixed = true, s.position = {0, 0, 2 * r};
  const std::int64_t held = sim.add_particle(s);
  // A fixed grain far smaller than the floor's travel in a step: the floor passes
  // it too, without a "steps over" stop (it touches no wall).
  s.radius = 1e-3 * r, s.position = {0.05, 0, 2 * r};
  sim.add_particle(s);
  s.radius = r, s.position = {0.1, 0, 0.1}, s.fixed = false;
  const std::int64_t far = sim.add_particle(s);  // a free one far above
  sim.advance(1);
  REQUIRE(1.0 * sim.time_step() > 1e-3 * r);  // 1 m/s times a step: past the grain's radius
  while (sim.time() < 4 * r)
    REQUIRE_NOTHROW(sim.advance(100));  // the floor, at 1 m/s, is now past both
  CHECK_THROWS_WITH(sim.set_fixed(held, false), Catch::Contains("would lie outside wall 'floor'"));
  CHECK(sim.stats().free_mass == Approx(mass).epsilon(1e-12));
  // Another change that prepares the scene anew finds the fixed spheres behind the
  // floor where they are, not through it.
  sim.set_fixed(far, true);
  sim.set_fixed(far, false);
  CHECK_NOTHROW(sim.advance(100));
}

TEST_CASE("set_fixed: freeing a bonded particle meets the bonds' stability limit", "[set_fixed]") {
  // A light sphere (radius r) bonded to a heavy one (2 r): the limit is the
  // stiffest free particle's, so with the light one fixed it is the heavy one's,
  // and freeing the light one lowers it; a step between the two limits is
  // refused by name once it is freed.
  auto pair = [](Simulation<3>& sim, bool first_fixed) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"glass", density, 0, 0, 0});
    sim.set_contact("glass", "glass", "linear", {{"k_normal", 1e2}, {"restitution", 0.5}});
    sim.set_time_step(1e-9);
    ParticleSpec s;
    s.radius = r, s.material = 0, s.fixed = first_fixed;
    const std::int64_t first = sim.add_particle(s);
    s.position = {3 * r, 0, 0}, s.radius = 2 * r, s.fixed = false;
    sim.add_particle(s);
    BondSpec b;
    b.material_a = b.material_b = 0, b.gap = 1e-9;
    b.normal_stiffness = 1e13, b.shear_stiffness = 5e12;
    b.tensile_strength = b.shear_strength = 1e12;
    REQUIRE(sim.create_bonds(b) == 1);
    return first;
  };
  // The limit with both free, from the refusal's message.
  double limit_free = 0;
  {
    Simulation<3> both;
    pair(both, false);
    both.set_time_step(1e-5);  // within the contact law's limit, far past the bond's
    try {
      both.advance(1);
      FAIL("a step of 10 us beside a stiff bond was taken");
    } catch (const InputError& e) {
      const std::string message = e.what();
      const auto at = message.find("1/omega = ");
      REQUIRE(at != std::string::npos);
      limit_free = std::stod(message.substr(at + 10));
    }
  }
  REQUIRE(limit_free > 0);
  Simulation<3> sim;
  const std::int64_t first = pair(sim, true);
  sim.set_time_step(1.2 * limit_free);
  REQUIRE_NOTHROW(sim.advance(10));  // one free sphere: a longer limit
  sim.set_fixed(first, false);
  CHECK_THROWS_WITH(sim.advance(1), Catch::Contains("bonds' stability limit"));
}

TEST_CASE("set_fixed: a particle freed in the air falls as g t from rest", "[set_fixed]") {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.set_contact("glass", "glass", "linear", {{"k_normal", 1e4}, {"restitution", 0.5}});
  sim.set_gravity({0, 0, -g});
  ParticleSpec s;
  s.radius = r, s.material = 0, s.position = {0, 0, 1};
  s.velocity = {0.3, 0, 0};
  const std::int64_t p = sim.add_particle(s);
  s.position = {1, 0, 0}, s.velocity = {0, 0, 0};
  sim.add_particle(s);  // a second, far away: the scene has a contact law in use
  sim.advance(100);
  sim.set_fixed(p, true);
  const Triple held = sim.position(p);
  sim.advance(100);
  CHECK(sim.position(p) == held);
  sim.set_fixed(p, false);
  const double dt = sim.time_step();
  sim.advance(1000);
  // Leap-frog is exact for a constant force: v = -g t, no sideways speed left.
  CHECK(sim.velocity(p)[0] == 0);
  CHECK(sim.velocity(p)[2] == Approx(-g * 1000 * dt).epsilon(1e-12));
}

TEST_CASE("set_fixed: the time-step rule reads the particles left free", "[set_fixed]") {
  // The rule takes each material's smallest free particle: freeing the only small
  // one, fixed from the start, shortens the automatic step to what the scene with
  // it free takes (a step kept short when it is fixed again: an automatic step is
  // chosen again only when too long).
  auto scene = [](Simulation<3>& sim, bool small_fixed) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"glass", density, 0, 0, 0});
    sim.set_contact("glass", "glass", "linear", {{"k_normal", 1e4}, {"restitution", 0.5}});
    ParticleSpec s;
    s.radius = r, s.material = 0, s.fixed = small_fixed;
    const std::int64_t small = sim.add_particle(s);
    s.radius = 4 * r, s.position = {0.1, 0, 0}, s.fixed = false;
    sim.add_particle(s);
    sim.advance(1);
    return small;
  };
  Simulation<3> free_from_start;
  scene(free_from_start, false);
  Simulation<3> sim;
  const std::int64_t small = scene(sim, true);
  const double without_small = sim.time_step();
  CHECK(without_small > 2 * free_from_start.time_step());
  sim.set_fixed(small, false);
  sim.advance(1);
  CHECK(sim.time_step() == free_from_start.time_step());
  sim.set_fixed(small, true);
  sim.advance(1);
  CHECK(sim.time_step() == free_from_start.time_step());
  CHECK_THROWS_AS(sim.set_fixed(99, true), InputError);
}
