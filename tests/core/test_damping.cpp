// Simulation::set_damping (fields/damping.hpp): viscous damping against its
// closed forms (free decay e^{-c t}, terminal velocity g / c, spins likewise),
// Cundall's local damping against its (a fall from rest at (1 - alpha) g, a
// rebound of restitution-1 contact at sqrt((1 - alpha) / (1 + alpha))), in 2D
// and 3D; off it changes nothing, and a checkpoint keeps it.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double r = 1e-3, density = 2500, g = 9.81;

// One free sphere (or disk) with a friction law to a floor far below: spins
// are integrated, nothing touches until a test lets it fall.
template <int D>
void scene(Simulation<D>& sim, double dt, double floor_at = -1.0, double friction = 0.5) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.add_material({"steel", 0, 0, 0, 0});
  sim.set_contact("glass", "glass", "linear",
                  {{"k_normal", 1e4}, {"restitution", 1.0}, {"friction", friction}});
  sim.set_contact("glass", "steel", "linear",
                  {{"k_normal", 1e4}, {"restitution", 1.0}, {"friction", friction}});
  WallSpec w;
  w.name = "floor", w.material = 1;
  w.normal = D == 3 ? Triple{0, 0, 1} : Triple{0, 1, 0};
  w.point = D == 3 ? Triple{0, 0, floor_at} : Triple{0, floor_at, 0};
  sim.add_wall(w);
  ParticleSpec s;
  s.radius = r, s.material = 0, s.position = {0, 0, 0};
  sim.add_particle(s);
  sim.set_time_step(dt);
}
constexpr int up(int d) {
  return d == 3 ? 2 : 1;
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("damping: viscous decay and terminal velocity follow their closed forms",
                       "[damping]", ((int D), D), 2, 3) {
  const double dt = 1e-5, c = 200, c_w = 50;
  Simulation<D> sim;
  scene(sim, dt);
  sim.set_damping({c, c_w, 0});
  const Triple v0 = D == 3 ? Triple{0.3, -0.2, 0.1} : Triple{0.3, -0.2, 0};
  const Triple w0 = D == 3 ? Triple{5, -3, 2} : Triple{0, 0, 5};
  sim.set_velocity(0, v0);
  sim.set_spin(0, w0);
  const int steps = 1000;  // c t = 2: e^-2 of the speed left
  sim.advance(steps);
  const double t = steps * dt;
  for (int k = 0; k < 3; ++k) {
    // Stepped exactly: e^{-c t} to round-off, whatever c dt.
    CHECK(sim.velocity(0)[k] == Approx(v0[k] * std::exp(-c * t)).margin(1e-15).epsilon(1e-12));
    CHECK(sim.spin(0)[k] == Approx(w0[k] * std::exp(-c_w * t)).margin(1e-15).epsilon(1e-12));
  }
  // Positions: each step moves by its half-step velocity, v0 e^{-c n dt} at step n.
  double travelled = 0;
  for (int n = 1; n <= steps; ++n) travelled += dt * std::exp(-c * n * dt);
  CHECK(sim.position(0)[0] == Approx(v0[0] * travelled).epsilon(1e-10));

  // Under gravity a particle reaches g / c from rest, exactly at any step
  // (here c dt = 2, where explicit Euler would be unstable).
  const double c_fall = 2 / dt;
  Simulation<D> falling;
  scene(falling, dt, -1e3);
  Triple down{0, 0, 0};
  down[up(D)] = -g;
  falling.set_gravity(down);
  falling.set_damping({c_fall, 0, 0});
  falling.advance(100);
  CHECK(falling.velocity(0)[up(D)] == Approx(-g / c_fall).epsilon(1e-12));
  CHECK(std::isfinite(falling.position(0)[up(D)]));

  // A rate so small that c dt underflows damps nothing (not: stops every force).
  Simulation<D> tiny;
  scene(tiny, dt, -1e3);
  tiny.set_gravity(down);
  tiny.set_damping({1e-320, 0, 0});
  tiny.advance(100);
  CHECK(tiny.velocity(0)[up(D)] == Approx(-g * 100 * dt).epsilon(1e-12));

  // Without friction no torque acts, yet spin damping slows the spins the scene set.
  Simulation<D> smooth;
  scene(smooth, dt, -1.0, 0.0);
  smooth.set_spin(0, w0);
  smooth.set_damping({0, c_w, 0});
  smooth.advance(steps);
  CHECK(smooth.effects().rotation);
  for (int k = 0; k < 3; ++k)
    CHECK(smooth.spin(0)[k] == Approx(w0[k] * std::exp(-c_w * t)).margin(1e-15).epsilon(1e-12));
}

TEMPLATE_TEST_CASE_SIG("damping: local damping follows its closed forms", "[damping]", ((int D), D),
                       2, 3) {
  const double alpha = 0.3;
  // From rest under gravity the force drives the motion: the fall goes at
  // (1 - alpha) g, step by step.
  {
    const double dt = 1e-5;
    Simulation<D> sim;
    scene(sim, dt);
    Triple down{0, 0, 0};
    down[up(D)] = -g;
    sim.set_gravity(down);
    sim.set_damping({0, 0, alpha});
    sim.advance(1000);
    CHECK(sim.velocity(0)[up(D)] == Approx(-(1 - alpha) * g * 1000 * dt).epsilon(1e-12));
    // Thrown up, gravity opposes the motion: it decelerates at (1 + alpha) g.
    Triple v_up{0, 0, 0};
    v_up[up(D)] = 0.1;
    sim.set_velocity(0, v_up);
    sim.advance(100);
    CHECK(sim.velocity(0)[up(D)] == Approx(0.1 - (1 + alpha) * g * 100 * dt).epsilon(1e-12));
  }
  // No force, no damping: a free particle flies on.
  {
    Simulation<D> sim;
    scene(sim, 1e-5);
    sim.set_damping({0, 0, alpha});
    sim.set_velocity(0, {0.2, 0.1, 0});
    sim.advance(500);
    CHECK(sim.velocity(0)[0] == 0.2);
    CHECK(sim.velocity(0)[1] == 0.1);
  }
  // A normal impact on a wall with an undamped linear contact (restitution 1):
  // compression against the motion at (1 + alpha) k, restitution with it at
  // (1 - alpha) k, so the rebound speed is sqrt((1 - alpha) / (1 + alpha)) of the
  // approach; the switch lands within a step of the turning point.
  {
    const double v_in = 0.05;
    const double mass = 4.0 / 3.0 * M_PI * r * r * r * density;  // a sphere in 2D too
    const double t_c = M_PI * std::sqrt(mass / 1e4);             // the undamped contact's duration
    const double dt = t_c / 2000;
    Simulation<D> sim;
    scene(sim, dt, -1.001 * r);
    sim.set_damping({0, 0, alpha});
    Triple v{0, 0, 0};
    v[up(D)] = -v_in;
    sim.set_velocity(0, v);
    sim.advance(static_cast<std::int64_t>((0.001 * r / v_in + 2 * t_c) / dt));
    const double e = sim.velocity(0)[up(D)] / v_in;
    CHECK(e == Approx(std::sqrt((1 - alpha) / (1 + alpha))).epsilon(2e-3));
  }
}

TEST_CASE("damping: off changes nothing, and a checkpoint keeps it", "[damping]") {
  auto run = [](int mode) {
    Simulation<3> sim;
    scene(sim, 1e-5, -0.5 * r);  // on the floor, overlapping it: a contact from the start
    sim.set_gravity({0, 0, -g});
    sim.set_velocity(0, {0.01, 0, 0});
    if (mode == 1) sim.set_damping({100, 20, 0.2}), sim.set_damping({});
    sim.advance(500);
    return sim.position(0);
  };
  CHECK(run(0) == run(1));  // on then off: bit for bit as never on

  Simulation<3> sim;
  scene(sim, 1e-5, -0.9 * r);
  sim.set_gravity({0, 0, -g});
  sim.set_damping({100, 20, 0.2});
  sim.set_velocity(0, {0.01, 0, 0});
  sim.advance(300);
  const StateBlob saved = sim.save_state();
  REQUIRE(saved.doubles.at("damping") == std::vector<double>{100, 20, 0.2});
  sim.advance(300);
  Simulation<3> resumed;
  scene(resumed, 1e-5, -0.9 * r);
  resumed.set_gravity({0, 0, -g});
  resumed.load_state(saved);
  CHECK(resumed.damping().viscous == 100);
  resumed.advance(300);
  CHECK(resumed.position(0) == sim.position(0));
  CHECK(resumed.spin(0) == sim.spin(0));
  // Damaged values are refused by name.
  for (const auto& bad : std::vector<std::vector<double>>{
           {100, 20, 1.0}, {-1, 20, 0.2}, {100, NAN, 0.2}, {100, 20}}) {
    StateBlob damaged = saved;
    damaged.doubles["damping"] = bad;
    Simulation<3> refused;
    scene(refused, 1e-5, -0.9 * r);
    CHECK_THROWS_WITH(refused.load_state(damaged), Catch::Contains("'damping'"));
  }
}

TEMPLATE_TEST_CASE_SIG("damping: local damping slows rolling down a slope to (1 - alpha) of it",
                       "[damping]", ((int D), D), 2, 3) {
  // A sphere rolling without slip down a slope: a = (1 - alpha) (5/7) g sin theta
  // (a 2D particle is a sphere moving in the plane), both the force and the
  // torque reduced by alpha, so it keeps rolling. Gravity tilted by theta over a
  // level floor; the contact stiff and damped, friction high enough not to slip.
  const double theta = 0.3, alpha = 0.4;
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", density, 0, 0, 0});
  sim.add_material({"steel", 0, 0, 0, 0});
  sim.set_contact("glass", "steel", "linear",
                  {{"k_normal", 1e5}, {"restitution", 0.3}, {"friction", 1.0}});
  WallSpec w;
  w.name = "floor", w.material = 1;
  w.normal = D == 3 ? Triple{0, 0, 1} : Triple{0, 1, 0};
  w.point = {0, 0, 0};
  sim.add_wall(w);
  ParticleSpec s;
  s.radius = r, s.material = 0;
  s.position = D == 3 ? Triple{0, 0, r} : Triple{0, r, 0};
  sim.add_particle(s);
  Triple down{0, 0, 0};
  down[0] = g * std::sin(theta);
  down[up(D)] = -g * std::cos(theta);
  sim.set_gravity(down);
  sim.set_damping({0, 0, alpha});
  sim.advance(2000);  // the contact settles and rolling sets in
  const double t0 = sim.time(), v0 = sim.velocity(0)[0];
  sim.advance(20000);
  const double expected = (1 - alpha) * 5.0 / 7.0 * g * std::sin(theta);
  CHECK((sim.velocity(0)[0] - v0) / (sim.time() - t0) == Approx(expected).epsilon(1e-3));
  // Rolling, not sliding: the contact point at rest (spin about -z in 2D, +y in 3D).
  const double spin = D == 3 ? sim.spin(0)[1] : -sim.spin(0)[2];
  CHECK(std::abs(sim.velocity(0)[0] - spin * r) < 1e-3 * std::abs(sim.velocity(0)[0]));
}

TEST_CASE("damping: bad values are refused naming the parameter", "[damping]") {
  Simulation<3> sim;
  scene(sim, 1e-5);
  CHECK_THROWS_WITH(sim.set_damping({-1, 0, 0}), Catch::Contains("'viscous'"));
  CHECK_THROWS_WITH(sim.set_damping({0, NAN, 0}), Catch::Contains("'spin'"));
  CHECK_THROWS_WITH(sim.set_damping({0, 0, 1}), Catch::Contains("'local_fraction'"));
  CHECK_THROWS_WITH(sim.set_damping({0, 0, -0.1}), Catch::Contains("'local_fraction'"));
  CHECK_FALSE(sim.damping().active());  // a refused call changes nothing
}
