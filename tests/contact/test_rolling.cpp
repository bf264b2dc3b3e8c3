// Rolling resistance (contact/rolling.hpp) against closed forms, through the
// engine: one sphere on a plane wall under gravity.
//
// A sphere (mass m, radius r, moment of inertia I about its centre) rolling
// without slip on a plane against a constant torque M = mu_r r N with N = m g
// decelerates at a = M r / (I + m r^2) = mu_r g / (1 + I / (m r^2)), and so
// stops after d = v0^2 (1 + I / (m r^2)) / (2 mu_r g): for a solid sphere
// (I = 2/5 m r^2) d = 0.7 v0^2 / (mu_r g). Granule's 2D particles are spheres
// moving in a plane (core/types.hpp: sphere mass and inertia in both
// dimensions), so the 2D distance is the same; a disk (I = 1/2 m r^2) would
// stop after 0.75 v0^2 / (mu_r g). The test takes I from the engine's
// particle, so it holds for either.
// On an incline of angle theta (gravity tilted instead of the plane), the
// sphere at rest holds while the torque the friction force needs, m g sin(theta) r,
// stays below mu_r r N = mu_r r m g cos(theta): tan(theta) < mu_r; above, it
// rolls with a = g (sin(theta) - mu_r cos(theta)) / (1 + I / (m r^2)).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "contact/models.hpp"
#include "contact/rolling.hpp"
#include "engine/simulation.hpp"
#include "io/contact_histories.hpp"

using namespace granule;

namespace {

constexpr double radius = 1e-3, density = 2500, k_normal = 1e3, g = 9.81;

struct Floor {
  std::unique_ptr<SimulationBase> sim;
  std::int64_t id = 0;
  double mass = 0, inertia = 0;
  // I / (m r^2) of the engine's particle.
  double inertia_ratio() const { return inertia / (mass * radius * radius); }
};

// A sphere resting (at its equilibrium overlap) on the wall y = 0, gravity
// at angle `tilt` from -y towards +x, moving along x at v0 and rolling
// without slip.
template <int D>
Floor floor_scene(const ParamValues& rolling, double tilt, double v0) {
  Floor f;
  auto sim = std::make_unique<Simulation<D>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", density, 0, 0, 0});
  sim->add_material({"w", 0, 0, 0, 0});
  ParamValues law{{"k_normal", k_normal}, {"restitution", 0.5}, {"friction", 0.9}};
  for (const auto& [k, v] : rolling) law[k] = v;
  sim->set_contact("p", "p", "linear", law);
  sim->set_contact("p", "w", "linear", law);
  sim->set_gravity({g * std::sin(tilt), -g * std::cos(tilt), 0});
  WallSpec w;
  w.name = "floor";
  w.material = 1;
  w.normal = {0, 1, 0};
  sim->add_wall(w);
  f.mass = sphere_mass(radius, density);
  f.inertia = sphere_inertia(f.mass, radius);
  ParticleSpec s;
  s.radius = radius;
  s.material = 0;
  s.position = {0, radius - f.mass * g * std::cos(tilt) / k_normal, 0};
  s.velocity = {v0, 0, 0};
  s.spin = {0, 0, -v0 / radius};
  f.id = sim->add_particle(s);
  sim->prepare();
  f.sim = std::move(sim);
  return f;
}

// Kinetic, gravitational and normal-spring energy of the floor's sphere.
double energy(const Floor& f, double tilt) {
  const Triple x = f.sim->position(f.id), v = f.sim->velocity(f.id), w = f.sim->spin(f.id);
  const double v_sq = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const double w_sq = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  const double height = -(std::sin(tilt) * x[0] - std::cos(tilt) * x[1]);  // along -g
  const double overlap = std::max(0.0, radius - x[1]);
  return 0.5 * f.mass * v_sq + 0.5 * f.inertia * w_sq + f.mass * g * height +
         0.5 * k_normal * overlap * overlap;
}

template <int D>
void check_stopping_distance(const ParamValues& rolling) {
  const double mu_r = rolling.at("rolling_friction"), v0 = 0.05;
  Floor f = floor_scene<D>(rolling, 0, v0);
  const double ratio = f.inertia_ratio();
  const double expected = v0 * v0 * (1 + ratio) / (2 * mu_r * g);
  const double stop_time = v0 * (1 + ratio) / (mu_r * g);
  const double dt = f.sim->time_step();
  const auto steps = static_cast<std::int64_t>(1.3 * stop_time / dt);
  const double e0 = energy(f, 0);
  double highest = e0;
  for (std::int64_t k = 0; k < steps; ++k) {
    f.sim->advance(1);
    highest = std::max(highest, energy(f, 0));
  }
  const double travelled = f.sim->position(f.id)[0];
  INFO(D << "D, rolling_model " << rolling.count("rolling_model") << ": travelled " << travelled
         << " m, closed form " << expected << " m; spin now " << f.sim->spin(f.id)[2]
         << " rad/s; energy rose by " << (highest - e0) / e0 << " of E0");
  CHECK(std::abs(travelled - expected) <= 0.01 * expected);
  // It has stopped: the speed is far below the v0 it started with.
  CHECK(std::abs(f.sim->velocity(f.id)[0]) <= 1e-3 * v0);
  CHECK(highest <= e0 * (1 + 1e-6));  // energy never rises
}

// A sphere spinning in place on a frictionless plane (so nothing but the
// rolling torque turns it): the constant torque mu_r r m g decelerates the
// spin at mu_r r m g / I and must stop it at zero, never through it, after
// t = w0 I / (mu_r r m g).
template <int D>
void check_spin_stops(double mu_r) {
  const ParamValues rolling{
      {"rolling_friction", mu_r}, {"rolling_model", rolling_model::constant}, {"friction", 0}};
  const double w0 = -50;
  Floor f = floor_scene<D>(rolling, 0, 0);
  f.sim->set_spin(f.id, {0, 0, w0});
  const double stop_time = -w0 * f.inertia / (mu_r * radius * f.mass * g);
  const double dt = f.sim->time_step();
  double stopped_at = -1, most_reversed = -1e300;
  const auto steps = static_cast<std::int64_t>(1.5 * stop_time / dt);
  for (std::int64_t k = 0; k < steps; ++k) {
    f.sim->advance(1);
    const double w = f.sim->spin(f.id)[2];
    most_reversed = std::max(most_reversed, w);
    if (stopped_at < 0 && std::abs(w) <= 1e-12 * std::abs(w0)) stopped_at = f.sim->time();
  }
  INFO(D << "D: spin stopped at t = " << stopped_at << " s (closed form " << stop_time
         << " s); largest spin " << most_reversed << " rad/s (started at " << w0 << ")");
  // Never reversed beyond round-off (without the cap on |M| it would swing by
  // mu_r r m g dt / I, ~1e-2 rad/s here, every step), and at rest it stays at zero.
  CHECK(most_reversed <= 1e-12 * std::abs(w0));
  CHECK(std::abs(f.sim->spin(f.id)[2]) <= 1e-12 * std::abs(w0));
  CHECK(std::abs(stopped_at - stop_time) <= 2 * dt + 1e-3 * stop_time);
}

}  // namespace

TEST_CASE("rolling: a constant torque stops a rolling sphere within v0^2 (1 + I/mr^2)/(2 mu_r g)",
          "[rolling]") {
  const ParamValues constant{{"rolling_friction", 0.1}, {"rolling_model", rolling_model::constant}};
  check_stopping_distance<3>(constant);
  check_stopping_distance<2>(constant);
  // The EPSD spring slips at the same torque while it rolls.
  const ParamValues epsd{{"rolling_friction", 0.1}, {"rolling_damping", 0.3}};
  check_stopping_distance<3>(epsd);
  check_stopping_distance<2>(epsd);
}

TEST_CASE("rolling: the constant torque stops a free spin at zero and never reverses it",
          "[rolling]") {
  check_spin_stops<3>(0.1);
  check_spin_stops<2>(0.1);
}

TEST_CASE("rolling: a sphere on an incline holds below tan(theta) = mu_r and rolls above it",
          "[rolling]") {
  const double mu_r = 0.2, time = 0.05;
  for (const double model : {rolling_model::epsd, rolling_model::constant}) {
    for (const double tan_theta : {0.8 * mu_r, 1.25 * mu_r}) {
      for (const int dim : {2, 3}) {
        const double tilt = std::atan(tan_theta);
        // The EPSD spring with its dashpot (eta_r = 0.3): undamped, the spring and the
        // tangential spring ring on after the release.
        const ParamValues rolling{{"rolling_friction", mu_r},
                                  {"rolling_model", model},
                                  {"rolling_damping", model == rolling_model::epsd ? 0.3 : 0.0}};
        Floor f = dim == 2 ? floor_scene<2>(rolling, tilt, 0) : floor_scene<3>(rolling, tilt, 0);
        const auto steps = static_cast<std::int64_t>(time / f.sim->time_step());
        const double e0 = energy(f, tilt);
        double highest = e0, t1 = 0, v1 = 0;
        for (std::int64_t k = 0; k < steps; ++k) {
          f.sim->advance(1);
          highest = std::max(highest, energy(f, tilt));
          if (k == steps / 5) t1 = f.sim->time(), v1 = f.sim->velocity(f.id)[0];
        }
        const double t = f.sim->time();
        const double travelled = f.sim->position(f.id)[0];
        const double s = std::sin(tilt), c = std::cos(tilt);
        const double free_roll = 0.5 * g * s / (1 + f.inertia_ratio()) * t * t;  // mu_r = 0
        INFO(dim << "D, model " << model << ", tan(theta)/mu_r " << tan_theta / mu_r
                 << ": travelled " << travelled << " m in " << t << " s (free rolling " << free_roll
                 << " m)");
        if (tan_theta < mu_r) {
          CHECK(std::abs(travelled) <= 1e-3 * free_roll);
        } else {
          // The acceleration once rolling (from t/5 on, past the release's transient).
          const double expected = g * (s - mu_r * c) / (1 + f.inertia_ratio());
          const double measured = (f.sim->velocity(f.id)[0] - v1) / (t - t1);
          INFO("acceleration " << measured << " m/s^2, closed form " << expected);
          CHECK(std::abs(measured - expected) <= 0.01 * expected);
        }
        // The energy released is at most what gravity gave (nothing rises above E0
        // but the rolling's share of the fall, which `energy` counts as height).
        CHECK(highest <= e0 + 1e-6 * std::abs(e0) + 1e-18);
      }
    }
  }
}

TEST_CASE("rolling: rolling parameters are checked and chosen per pair", "[rolling]") {
  Simulation<3> sim;
  sim.add_material({"p", density, 0, 0, 0});
  // Without rolling_friction or twisting_friction the other rolling parameters
  // are refused, naming both.
  CHECK_THROWS_WITH(
      sim.set_contact("p", "p", "linear",
                      {{"k_normal", 1e3}, {"restitution", 1}, {"rolling_model", 1}}),
      Catch::Contains("rolling_friction > 0") && Catch::Contains("twisting_friction > 0"));
  CHECK_THROWS_WITH(
      sim.set_contact("p", "p", "linear",
                      {{"k_normal", 1e3}, {"restitution", 1}, {"rolling_friction", -0.1}}),
      Catch::Contains("rolling_friction"));
  CHECK_THROWS_WITH(rolling_model_code("spring", "contact 'p'-'p'"),
                    Catch::Contains("contact 'p'-'p'") && Catch::Contains("epsd, constant"));
  // rolling_friction = 0 is the plain law; > 0 its rolling variant.
  sim.set_contact("p", "p", "linear",
                  {{"k_normal", 1e3}, {"restitution", 1}, {"rolling_friction", 0}});
  CHECK(sim.pair_table().at(0, 0).model == contact_model_id("linear"));
  sim.set_contact("p", "p", "linear",
                  {{"k_normal", 1e3}, {"restitution", 1}, {"rolling_friction", 0.1}});
  CHECK(sim.pair_table().at(0, 0).model == rolling_contact_model(contact_model_id("linear")));
  // A run may change mu_r, not remove the term.
  sim.update_contact("p", "p", {{"rolling_friction", 0.2}});
  CHECK_THROWS_WITH(sim.update_contact("p", "p", {{"rolling_friction", 0}}),
                    Catch::Contains("must stay > 0"));
}

namespace {
// A sphere spinning at w0 about z strikes the frictionless floor at (vx, -vy),
// no gravity: only the rolling torque turns it, so |I dw| <= mu_r r J_n, J_n the
// normal impulse (allow_tension = 0 keeps N >= 0, so J_n is the sum of N dt).
template <int D>
double rolling_impulse_ratio(double mu_r, double eta) {
  const ParamValues law{
      {"k_normal", k_normal}, {"restitution", 0.5},       {"friction", 0},
      {"allow_tension", 0},   {"rolling_friction", mu_r}, {"rolling_damping", eta}};
  auto sim = std::make_unique<Simulation<D>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", density, 0, 0, 0});
  sim->add_material({"w", 0, 0, 0, 0});
  sim->set_contact("p", "p", "linear", law);
  sim->set_contact("p", "w", "linear", law);
  WallSpec w;
  w.name = "floor";
  w.material = 1;
  w.normal = {0, 1, 0};
  sim->add_wall(w);
  ParticleSpec s;
  s.radius = radius;
  s.material = 0;
  s.position = {0, 1.001 * radius, 0};
  s.velocity = {0.1, -0.1, 0};
  s.spin = {0, 0, -100};
  const std::int64_t id = sim->add_particle(s);
  const double mass = sphere_mass(radius, density), inertia = sphere_inertia(mass, radius);
  // Contact time pi sqrt(m / k) ~ 3.2e-3 s: 0.02 s covers the approach and the impact.
  sim->prepare();
  sim->advance(static_cast<std::int64_t>(0.02 / sim->time_step()));
  REQUIRE(sim->stats().contacts_wall == 0);  // bounced off
  const double impulse = mass * (sim->velocity(id)[1] + 0.1);
  REQUIRE(impulse > 0);
  return inertia * std::abs(sim->spin(id)[2] + 100) / (mu_r * radius * impulse);
}
}  // namespace

TEST_CASE("rolling: the epsd torque, spring and dashpot together, stays within mu_r R* N",
          "[rolling]") {
  // Ai's dashpot below the cap is unbounded: through an impact, where N rises
  // faster than the spring, it resisted by more than the cap in all (eta = 0.3, 1).
  for (const double eta : {0.0, 0.3, 1.0}) {
    const double r3 = rolling_impulse_ratio<3>(0.1, eta), r2 = rolling_impulse_ratio<2>(0.1, eta);
    INFO("eta_r " << eta << ": |I dw| / (mu_r r J_n) = " << r3 << " (3D), " << r2 << " (2D)");
    CHECK(r3 <= 1 + 1e-9);
    CHECK(r2 <= 1 + 1e-9);
    CHECK(r3 > 0.3);  // the torque acted
  }
}

TEST_CASE("rolling: the epsd spring's own mode bounds the time step", "[rolling]") {
  // Without friction the spring turns the sphere about its own centre:
  // omega_r^2 = k_r / I = (2.25 / 0.4) mu_r^2 k_n / m, 2.37 mu_r omega_n on a
  // wall. The limit is 1 / omega (half of leap-frog's 2 / omega). At mu_r = 20
  // the automatic step puts it far past leap-frog's limit, where the spin
  // chatters step by step.
  auto scene = [](double mu_r, double model, double time_step = 0, double w0 = 0,
                  double* largest = nullptr) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", density, 0, 0, 0});
    sim.add_material({"w", 0, 0, 0, 0});
    const ParamValues law{{"k_normal", k_normal},
                          {"restitution", 0.5},
                          {"rolling_friction", mu_r},
                          {"rolling_model", model}};
    sim.set_contact("p", "p", "linear", law);
    sim.set_contact("p", "w", "linear", law);
    WallSpec w;
    w.name = "floor";
    w.material = 1;
    w.normal = {0, 1, 0};
    sim.add_wall(w);
    ParticleSpec s;
    s.radius = radius;
    s.material = 0;
    s.position = {0, radius, 0};
    s.spin = {0, 0, w0};
    const std::int64_t id = sim.add_particle(s);
    if (time_step > 0) sim.set_time_step(time_step);
    sim.prepare();
    if (largest) {  // the spin rings undamped for 2000 steps
      for (int k = 0; k < 2000; ++k) {
        sim.advance(1);
        *largest = std::max(*largest, std::abs(sim.spin(id)[2]));
      }
    }
    return sim.time_step_rule().stability_limit;
  };
  const double plain = scene(0.3, rolling_model::epsd);  // ratio 0.71: the law's own limit
  const double ratio = std::sqrt(2.25 / 0.4) * 0.7;
  const double limit = scene(0.7, rolling_model::epsd);
  CHECK(limit == Approx(plain / ratio));
  CHECK(scene(2, rolling_model::epsd) == Approx(plain / (std::sqrt(2.25 / 0.4) * 2)));
  CHECK(scene(20, rolling_model::constant) == Approx(plain));  // no spring, no mode
  CHECK_THROWS_WITH(scene(20, rolling_model::epsd),
                    Catch::Contains("stability limit") && Catch::Contains("p-p"));
  // The step that a bound with I + m r^2 (1.27 mu_r omega_n, below 1 at
  // mu_r = 0.7) let through is refused: there omega_r dt = 0.9 ratio = 1.49,
  // past the limit's margin.
  CHECK_THROWS_WITH(scene(0.7, rolling_model::epsd, 0.9 * plain),
                    Catch::Contains("stability limit"));
  // At the limit the spring rings, undamped, and never gains: the spin, at
  // its largest when the spring is unloaded, stays within w0.
  double largest = 0;
  const double w0 = 1;
  scene(0.7, rolling_model::epsd, 0.99 * limit, w0, &largest);
  INFO("largest spin " << largest << " rad/s of " << w0);
  CHECK(largest <= (1 + 1e-9) * w0);
}

namespace {
// A sphere on a floor, no damping anywhere, let go at half its resting
// overlap so that its Hertzian normal load rings, rocking at w0 about z with
// the rolling spring unloaded (tools/twist_pump.lua -D term=rolling).
struct Rocker {
  std::unique_ptr<Simulation<3>> sim;
  std::int64_t id = 0;
  double rest = 0;  // the resting overlap
};
Rocker rocker(const char* model, double mu_r, double w0, double friction = 0.3) {
  const double e = 1e8, nu = 0.3;
  Rocker r;
  r.sim = std::make_unique<Simulation<3>>();
  Simulation<3>& sim = *r.sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", density, e, nu, 0});
  sim.add_material({"w", 0, e, nu, 0});
  ParamValues law{{"friction", friction}, {"rolling_friction", mu_r}};
  if (std::string(model) == "hertz_mindlin") law["restitution"] = 1;
  sim.set_contact("p", "w", model, law);
  sim.set_gravity({0, -g, 0});
  WallSpec w;
  w.name = "floor";
  w.material = 1;
  w.normal = {0, 1, 0};
  sim.add_wall(w);
  const double mass = sphere_mass(radius, density);
  const double e_star = e / (2 * (1 - nu * nu));
  r.rest = std::pow(3 * mass * g / (4 * e_star * std::sqrt(radius)), 2.0 / 3.0);
  ParticleSpec s;
  s.radius = radius;
  s.material = 0;
  s.position = {0, radius - 0.5 * r.rest, 0};
  s.spin = {0, 0, w0};
  r.id = sim.add_particle(s);
  sim.prepare();
  return r;
}
}  // namespace

TEST_CASE("rolling: a ringing normal load does not pump the rolling spring (its energy is kept)",
          "[rolling]") {
  // The rolling mode modulated by Hertz's k_n at the normal frequency, at mu_r
  // where that is about twice the mode's own. hertz_mindlin without friction:
  // the sphere turns about its centre, k_r / I = (2.25 / 0.4) mu_r^2 k_n / m,
  // resonant at 0.211; thornton_elastic with friction: it rocks on the floor,
  // resonant near 0.6 (the secant k_n). A spring holding M_k was pumped to 0.71
  // and 0.47 rad/s over 0.1 s (build 245d0cd; tools/twist_pump.lua -D
  // term=rolling). Holding M_k / sqrt(k_r), the rolling mode's energy is kept.
  // (hertz_mindlin with friction still pumps the rocking, through its
  // tangential spring, which holds its displacement while 8 G* a follows the
  // overlap: docs/contact_models.md.)
  const double w0 = 0.01;
  struct Case {
    const char* model;
    double mu_r, friction;
  };
  for (const Case& c : {Case{"hertz_mindlin", 0.211, 0.0}, Case{"thornton_elastic", 0.6, 0.3}}) {
    const char* model = c.model;
    const double mu_r = c.mu_r;
    Rocker r = rocker(model, mu_r, w0, c.friction);
    Simulation<3>& sim = *r.sim;
    double largest = 0, first_half = 0, deepest = 0, shallowest = 1;
    const auto steps = static_cast<std::int64_t>(0.1 / sim.time_step());
    for (std::int64_t k = 0; k < steps; ++k) {
      sim.advance(1);
      largest = std::max(largest, std::abs(sim.spin(r.id)[2]));
      if (k == steps / 2) first_half = largest;
      const double overlap = radius - sim.position(r.id)[1];
      deepest = std::max(deepest, overlap), shallowest = std::min(shallowest, overlap);
    }
    INFO(model << ", mu_r " << mu_r << ": largest rocking spin " << largest << " rad/s ("
               << first_half << " in the first half; w0 " << w0 << "), overlap "
               << shallowest / r.rest << "-" << deepest / r.rest << " of the rest");
    REQUIRE(shallowest > 0);          // it stayed on the floor
    REQUIRE(deepest > 1.3 * r.rest);  // and the normal load rang
    CHECK(largest <= 1.1 * w0);
    CHECK(largest <= 1.001 * first_half);
  }
}

TEST_CASE(
    "rolling: a checkpoint whose wound springs hold torques (older builds) is refused "
    "where the stiffness follows the overlap",
    "[rolling][checkpoint]") {
  Rocker whole = rocker("hertz_mindlin", 0.3, 1.0);
  whole.sim->advance(200);
  StateBlob saved = whole.sim->save_state();
  {  // the spring is wound (one wall contact: its record's rolling spring)
    using Rolling = WithRolling<HertzMindlin, rolling_names::hertz_mindlin>;
    const auto& bytes = saved.bytes.at("walls.hertz_mindlin+rolling.history");
    REQUIRE(bytes.size() == sizeof(Rolling::History<3>));
    Rolling::History<3> h;
    std::memcpy(static_cast<void*>(&h), bytes.data(), sizeof h);
    REQUIRE(h.rolling.squaredNorm() > 0);
  }
  REQUIRE(saved.integers.count("rolling_springs"));
  whole.sim->advance(100);
  // This build's checkpoint restarts bit for bit.
  Rocker resumed = rocker("hertz_mindlin", 0.3, 1.0);
  resumed.sim->load_state(saved);
  resumed.sim->advance(100);
  CHECK(resumed.sim->spin(resumed.id) == whole.sim->spin(whole.id));
  CHECK(resumed.sim->position(resumed.id) == whole.sim->position(whole.id));
  // Without the key (older builds, which held M_k) a wound spring is refused by name.
  saved.integers.erase("rolling_springs");
  Rocker refused = rocker("hertz_mindlin", 0.3, 1.0);
  CHECK_THROWS_WITH(refused.sim->load_state(saved),
                    Catch::Contains("hertz_mindlin+rolling") && Catch::Contains("sqrt(k_r)"));
}

TEST_CASE(
    "rolling: contact histories saved by builds that held the springs' torques are refused "
    "where a non-linear law's spring is wound",
    "[rolling][checkpoint]") {
  // Two spheres overlapping (no gravity, no walls), the first spinning at w0.
  auto scene = [](const char* model, double w0) {
    auto sim = std::make_unique<Simulation<3>>();
    sim->set_warning_handler([](const std::string&) {});
    sim->add_material({"p", density, 1e8, 0.3, 0});
    ParamValues law{{"friction", 0.3}, {"rolling_friction", 0.1}};
    if (std::string(model) == "linear") law = {{"k_normal", k_normal}, {"restitution", 0.5}};
    if (std::string(model) != "thornton_elastic") law["restitution"] = 0.5;
    law["friction"] = 0.3, law["rolling_friction"] = 0.1;
    sim->set_contact("p", "p", model, law);
    for (int k = 0; k < 2; ++k) {
      ParticleSpec s;
      s.radius = radius;
      s.material = 0;
      s.position = {k * 1.999 * radius, 0, 0};
      if (k == 0) s.spin = {0, 0, w0};
      sim->add_particle(s);
    }
    sim->prepare();
    return sim;
  };
  for (const char* model : {"hertz_mindlin", "linear"}) {
    for (const double w0 : {0.0, 50.0}) {
      auto sim = scene(model, w0);
      sim->advance(5);  // the pair pushes itself apart within about 15 steps
      REQUIRE(sim->stats().contacts_particle == 1);
      StateBlob saved = io::pair_histories_of(sim->save_state(), {0, 1});
      REQUIRE(saved.integers.count("rolling_springs"));
      CHECK(sim->wound_legacy_rolling_springs(saved).empty());
      saved.integers.erase("rolling_springs");  // as older builds wrote them
      const bool wound = std::string(model) == "hertz_mindlin" && w0 > 0;
      INFO(model << ", w0 " << w0);
      CHECK(sim->wound_legacy_rolling_springs(saved) == (wound ? "hertz_mindlin+rolling" : ""));
      // What is not refused seeds as this build's own histories.
      auto fresh = scene(model, 0);
      StateBlob state = fresh->save_state();
      CHECK(io::seed_pair_histories(state, saved, {{0, 0}, {1, 1}}, "old.h5") == 1);
    }
  }
}

TEST_CASE("rolling: the deep-contact check's mode counts the springs' modes from the normal one",
          "[rolling]") {
  // hertz_mindlin with friction: its stiffest mode is the tangential one
  // (3.5 * 8 G* against 2 E*), so the springs' modes, ratio * omega_n, exceed
  // it only once ratio^2 > 14 G* / E*.
  using Rolling = WithRolling<HertzMindlin, rolling_names::hertz_mindlin>;
  const Material glass{"glass", 2500, 1e8, 0.3, 0};
  const PairMaterials pair{glass, glass};
  const PairScale scale{1e-6, 5e-4, 1e-6};
  const double overlap = 1e-6;
  for (const double mu_r : {0.1, 0.5, 2.0}) {
    ParamValues v{{"restitution", 0.5},       {"friction", 0.5},        {"shrink_rescale", 0},
                  {"rolling_friction", mu_r}, {"twisting_friction", 0}, {"rolling_model", 0},
                  {"rolling_damping", 0}};
    for (const ParamSpec& spec : Rolling::parameters())
      if (!v.count(spec.name)) v[spec.name] = spec.default_value;
    const Rolling::Params p = Rolling::make(v, pair);
    const double law = HertzMindlin::mode_squared(p.base, scale, overlap);
    const double normal = HertzMindlin::normal_mode_squared(p.base, scale, overlap);
    const double ratio = std::sqrt(2.25 / 0.4) * mu_r;
    INFO("mu_r " << mu_r << ": law " << law << ", normal " << normal);
    REQUIRE(law > 2 * normal);  // the tangential mode is the law's stiffest
    CHECK(Rolling::mode_squared(p, scale, overlap) ==
          Approx(std::max(law, ratio * ratio * normal)).epsilon(1e-12));
  }
}
