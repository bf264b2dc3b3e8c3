// Prescribed motion: a fixed particle given a velocity (and spin) moves
// uniformly whatever touches it (leapfrog.hpp), its contacts feel its motion,
// the lists follow it, and a checkpoint and freeing it keep the motion. In 2D
// and 3D; closed forms: x0 + v t, and a sphere struck by a body of infinite
// mass leaves at twice the body's speed.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double r = 1e-3, density = 2500;

template <int D>
Triple along(int axis, double value) {
  Triple t{0, 0, 0};
  t[static_cast<std::size_t>(axis)] = value;
  return t;
}

// Spheres (disks) of one material, an elastic linear law between them, no
// gravity unless a test sets it.
template <int D>
void materials(Simulation<D>& sim, double friction, double restitution = 1.0) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.set_contact("glass", "glass", "linear",
                  {{"k_normal", 1e4}, {"restitution", restitution}, {"friction", friction}});
}
template <int D>
std::int64_t sphere(Simulation<D>& sim, const Triple& at, bool fixed = false) {
  ParticleSpec s;
  s.radius = r, s.material = 0, s.position = at, s.fixed = fixed;
  return sim.add_particle(s);
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("prescribed motion: a fixed particle moves at the velocity set",
                       "[prescribed]", ((int D), D), 2, 3) {
  Simulation<D> sim;
  materials(sim, 0.5);
  sim.set_gravity(along<D>(1, -9.81));  // moves no fixed particle
  const Triple x0{0, 0, 0};
  const std::int64_t mover = sphere(sim, x0, true);
  // A free sphere resting on it from the start, pressed on by gravity.
  const std::int64_t other = sphere(sim, {0, 1.99 * r, 0});
  const Triple v = D == 3 ? Triple{0.03, -0.01, 0.02} : Triple{0.03, -0.01, 0};
  sim.set_velocity(mover, v);
  sim.set_time_step(1e-6);
  const int steps = 5000;
  sim.advance(steps);
  const double t = steps * 1e-6;
  for (int k = 0; k < D; ++k)
    CHECK(sim.position(mover)[k] == Approx(x0[k] + v[k] * t).margin(1e-15).epsilon(1e-12));
  CHECK(sim.velocity(mover) == v);  // exactly: nothing changes it
  (void)other;
  // Given with add_particle, the same.
  Simulation<D> added;
  materials(added, 0.5);
  ParticleSpec spec;
  spec.radius = r, spec.material = 0, spec.position = x0, spec.fixed = true, spec.velocity = v;
  const std::int64_t placed = added.add_particle(spec);
  added.set_time_step(1e-6);
  added.advance(steps);
  CHECK(added.position(placed) == sim.position(mover));
  // sim:describe() counts it as moving, however slow; fixed again, it stops.
  auto line = [](Simulation<D>& s) {
    for (const std::string& l : s.describe())
      if (l.rfind("particles:", 0) == 0) return l;
    return std::string();
  };
  CHECK(line(sim) == "particles: 2 (1 fixed, 1 of them moving as the scene set them)");
  sim.set_velocity(mover, along<D>(0, 5e-13));
  CHECK(line(sim) == "particles: 2 (1 fixed, 1 of them moving as the scene set them)");
  const Triple slow = sim.position(mover);
  sim.advance(1000);
  CHECK(sim.position(mover)[0] == Approx(slow[0] + 5e-13 * 1e-3).margin(5e-17));
  CHECK(sim.position(mover)[0] != slow[0]);
  sim.set_fixed(mover, true);
  CHECK(sim.velocity(mover) == Triple{0, 0, 0});
  CHECK(line(sim) == "particles: 2 (1 fixed)");
  // Set at rest again, it stays where it is, bit for bit.
  sim.set_velocity(mover, {0, 0, 0});
  const Triple stopped = sim.position(mover);
  sim.advance(100);
  CHECK(sim.position(mover) == stopped);
}

TEMPLATE_TEST_CASE_SIG("prescribed motion: a sphere struck head-on leaves at twice the speed",
                       "[prescribed]", ((int D), D), 2, 3) {
  // A body of infinite mass at U strikes a sphere at rest through an elastic
  // (e = 1) frictionless contact: in its frame the sphere comes at -U and
  // rebounds at +U, so it leaves at 2U; the body goes on at U.
  const double speed = 0.1;
  Simulation<D> sim;
  materials(sim, 0.0);
  const std::int64_t striker = sphere(sim, {0, 0, 0}, true);
  const std::int64_t target = sphere(sim, {2.2 * r, 0, 0});
  sim.set_velocity(striker, along<D>(0, speed));
  sim.set_time_step(1e-6);
  sim.advance(4000);  // 0.2 mm to close, ~0.1 ms of contact, then apart
  REQUIRE(sim.position(target)[0] - sim.position(striker)[0] > 2 * r);
  CHECK(sim.velocity(target)[0] == Approx(2 * speed).epsilon(1e-3));
  CHECK(std::abs(sim.velocity(target)[1]) < 1e-12);
  CHECK(sim.velocity(striker)[0] == speed);
  // The force it felt was the target's on it: during a contact it reads the
  // reaction (sim:particle(id).force), opposite to the target's.
  sim.set_position(target, {sim.position(striker)[0] + 1.999 * r, 0, 0});
  sim.set_velocity(target, {0, 0, 0});
  sim.advance(1);
  CHECK(sim.force(striker)[0] < 0);
  CHECK(sim.force(striker)[0] == Approx(-sim.force(target)[0]).epsilon(1e-12));
}

TEMPLATE_TEST_CASE_SIG("prescribed motion: the lists follow a fixed particle across a row",
                       "[prescribed]", ((int D), D), 2, 3) {
  // A fixed sphere sweeps along a row of 20 free spheres at rest, each just off
  // its line (so pushed aside, out of the way of the next) and 10 radii apart:
  // it travels many skins, and must strike every one.
  Simulation<D> sim;
  materials(sim, 0.0, 0.5);
  const std::int64_t sweeper = sphere(sim, {-3 * r, 0, 0}, true);
  const int count = 20;
  for (int k = 0; k < count; ++k) sphere(sim, {10 * r * k, 1.5 * r, 0});
  sim.set_velocity(sweeper, along<D>(0, 1.0));
  sim.set_time_step(2e-6);
  sim.advance(110000);  // 0.22 s: 0.22 m, past the row's end (0.19 m)
  REQUIRE(sim.position(sweeper)[0] > 10 * r * count);
  int struck = 0;
  for (std::int64_t id = 1; id <= count; ++id) struck += sim.velocity(id)[1] > 0;
  CHECK(struck == count);
  CHECK(sim.stats().list_rebuilds > 10);
}

TEMPLATE_TEST_CASE_SIG("prescribed motion: a turning fixed sphere drives what it touches",
                       "[prescribed]", ((int D), D), 2, 3) {
  // A fixed sphere turning about z under a free one resting on it (gravity
  // along -y): friction drags the contact point of the free sphere along the
  // surface's motion, -x for a spin about +z at the top of the lower sphere.
  Simulation<D> sim;
  materials(sim, 0.5, 0.3);
  sim.set_gravity(along<D>(1, -9.81));
  const std::int64_t wheel = sphere(sim, {0, 0, 0}, true);
  const std::int64_t rider = sphere(sim, {0, 1.999 * r, 0});
  sim.set_spin(wheel, D == 3 ? Triple{0, 0, 50} : Triple{0, 0, 50});
  sim.set_time_step(1e-6);
  sim.advance(2000);
  CHECK(sim.velocity(rider)[0] < 0);
  CHECK(sim.spin(wheel)[2] == 50);  // exactly: nothing changes it
  CHECK(sim.position(wheel) == Triple{0, 0, 0});
}

TEMPLATE_TEST_CASE_SIG("prescribed motion: a checkpoint keeps it, and freed it goes on",
                       "[prescribed]", ((int D), D), 2, 3) {
  auto scene = [](Simulation<D>& sim) {
    materials(sim, 0.4, 0.5);
    const std::int64_t mover = sphere(sim, {0, 0, 0}, true);
    for (int k = 1; k < 6; ++k) sphere(sim, {2.5 * r * k, 0.3 * r * (k % 2), 0});
    sim.set_velocity(mover, along<D>(0, 0.2));
    sim.set_time_step(1e-6);
  };
  Simulation<D> sim;
  scene(sim);
  sim.advance(20000);
  const StateBlob saved = sim.save_state();
  sim.advance(20000);
  Simulation<D> resumed;
  scene(resumed);
  resumed.load_state(saved);
  resumed.advance(20000);
  for (std::int64_t id = 0; id < 6; ++id) {
    CHECK(resumed.position(id) == sim.position(id));
    CHECK(resumed.velocity(id) == sim.velocity(id));
  }
  // Freed, it keeps its velocity; with nothing touching it, it flies on.
  Simulation<D> freed;
  materials(freed, 0.0);
  const std::int64_t lone = sphere(freed, {0, 0, 0}, true);
  freed.set_velocity(lone, along<D>(0, 0.2));
  freed.set_time_step(1e-6);
  freed.advance(10);
  freed.set_fixed(lone, false);
  CHECK(freed.velocity(lone)[0] == 0.2);
  freed.advance(10);
  CHECK(freed.velocity(lone)[0] == 0.2);
  // Fixed again, it stops.
  freed.set_fixed(lone, true);
  CHECK(freed.velocity(lone) == Triple{0, 0, 0});
}

TEST_CASE("prescribed motion: a fixed particle wraps across a periodic box", "[prescribed]") {
  constexpr int D = 3;  // a periodic axis is a 3D scene's
  // Periodic along x, 10 radii long: a fixed sphere at 2 m/s crosses the period
  // twice in 0.01 s and comes back in on the other side each time, its position
  // x0 + v t taken modulo the length; it strikes the free sphere it passes each time.
  const double length = 10 * r;
  Simulation<D> sim;
  materials(sim, 0.0, 0.5);
  sim.set_periodic(0, 0, length);
  const std::int64_t mover = sphere(sim, {0.5 * r, 0, 0}, true);
  const std::int64_t struck = sphere(sim, {5 * r, 1.5 * r, 0});
  sim.set_velocity(mover, along<D>(0, 2.0));
  sim.set_time_step(1e-6);
  sim.advance(10000);
  const double unwrapped = 0.5 * r + 2.0 * 0.01;
  const double expected = unwrapped - length * std::floor(unwrapped / length);
  CHECK(sim.position(mover)[0] == Approx(expected).margin(1e-12));
  CHECK(sim.position(mover)[0] >= 0);
  CHECK(sim.position(mover)[0] < length);
  CHECK(sim.velocity(struck)[1] > 0);  // pushed aside, away from its line
}
