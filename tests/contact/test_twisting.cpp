// Twisting resistance (contact/rolling.hpp: the rolling term's torque about
// the contact normal, 3D) against closed forms, through the engine.
//
// A sphere (mass m, radius r, moment of inertia I) resting on a plane under
// gravity and spinning at w0 about the plane's normal feels, once the twist
// slips, the torque M_t = mu_t R* N against its spin (R* = r on a wall, N = m g),
// and so stops after t = w0 I / (mu_t R* m g): with the constant torque, and
// with the epsd spring, which slips at the same torque while it turns. On top
// of a fixed sphere of radius r_j, R* = r r_j / (r + r_j). Spinning about the
// normal moves no point of the contact, so friction and rolling resistance
// leave such a spin alone: without twisting resistance it never stops.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "contact/rolling.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {

constexpr double radius = 1e-3, density = 2500, k_normal = 1e3, g = 9.81;

struct Spinner {
  std::unique_ptr<Simulation<3>> sim;
  std::int64_t id = 0;
  double mass = 0, inertia = 0, r_star = 0;
};

// A sphere of `radius` resting on the floor y = 0 (base_radius = 0) or on top
// of a fixed sphere of base_radius standing on it, spinning at w0 about y.
Spinner spinner(const ParamValues& extra, double w0, double base_radius = 0) {
  Spinner s;
  auto sim = std::make_unique<Simulation<3>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", density, 0, 0, 0});
  sim->add_material({"w", 0, 0, 0, 0});
  ParamValues law{{"k_normal", k_normal}, {"restitution", 0.5}, {"friction", 0.5}};
  for (const auto& [k, v] : extra) law[k] = v;
  sim->set_contact("p", "p", "linear", law);
  sim->set_contact("p", "w", "linear", law);
  sim->set_gravity({0, -g, 0});
  WallSpec w;
  w.name = "floor";
  w.material = 1;
  w.normal = {0, 1, 0};
  sim->add_wall(w);
  s.mass = sphere_mass(radius, density);
  s.inertia = sphere_inertia(s.mass, radius);
  const double sag = s.mass * g / k_normal;  // the resting overlap
  double bottom = 0;
  s.r_star = radius;
  if (base_radius > 0) {
    ParticleSpec base;
    base.radius = base_radius;
    base.material = 0;
    base.position = {0, base_radius, 0};
    base.fixed = true;
    sim->add_particle(base);
    bottom = 2 * base_radius;
    s.r_star = radius * base_radius / (radius + base_radius);
  }
  ParticleSpec p;
  p.radius = radius;
  p.material = 0;
  p.position = {0, bottom + radius - sag, 0};
  p.spin = {0, w0, 0};
  s.id = sim->add_particle(p);
  sim->prepare();
  s.sim = std::move(sim);
  return s;
}

// Runs 1.5 stopping times: when the spin first reached zero, its largest
// reversal after, and its value at the end.
struct SpinDown {
  double stop_time = 0, stopped_at = -1, most_reversed = 0, final_spin = 0;
};
SpinDown spin_down(Spinner& s, double w0, double mu_t, double run_factor = 1.5) {
  SpinDown out;
  out.stop_time = w0 * s.inertia / (mu_t * s.r_star * s.mass * g);
  const double dt = s.sim->time_step();
  const auto steps = static_cast<std::int64_t>(run_factor * out.stop_time / dt);
  for (std::int64_t k = 0; k < steps; ++k) {
    s.sim->advance(1);
    const double w = s.sim->spin(s.id)[1];
    if (out.stopped_at < 0 && w <= 1e-12 * w0) out.stopped_at = s.sim->time();
    if (out.stopped_at >= 0) out.most_reversed = std::min(out.most_reversed, w);
  }
  out.final_spin = s.sim->spin(s.id)[1];
  return out;
}

}  // namespace

TEST_CASE("twisting: a constant torque stops a spin about the normal at t = w0 I / (mu_t R* m g)",
          "[twisting]") {
  const double w0 = 50, mu_t = 0.1;
  const ParamValues law{{"twisting_friction", mu_t}, {"rolling_model", rolling_model::constant}};
  for (const double base : {0.0, 3 * radius}) {  // on the wall; on a fixed sphere 3x as large
    Spinner s = spinner(law, w0, base);
    const SpinDown d = spin_down(s, w0, mu_t);
    const double dt = s.sim->time_step();
    INFO("base radius " << base << ": stopped at " << d.stopped_at << " s (closed form "
                        << d.stop_time << " s), most reversed " << d.most_reversed
                        << " rad/s, final " << d.final_spin);
    CHECK(std::abs(d.stopped_at - d.stop_time) <= 2 * dt + 1e-3 * d.stop_time);
    // Never through zero (without the cap it would swing by mu_t R* m g dt / I a step).
    CHECK(d.most_reversed >= -1e-12 * w0);
    CHECK(std::abs(d.final_spin) <= 1e-12 * w0);
    // Nothing else moved: the sphere still sits on the axis.
    const Triple x = s.sim->position(s.id);
    CHECK(std::abs(x[0]) + std::abs(x[2]) <= 1e-12);
  }
}

TEST_CASE("twisting: the epsd spring slips at mu_t R* N, then its dashpot brings the spin to rest",
          "[twisting]") {
  const double w0 = 50, mu_t = 0.1;
  for (const double base : {0.0, 3 * radius}) {
    Spinner s = spinner({{"twisting_friction", mu_t}, {"rolling_damping", 0.3}}, w0, base);
    const SpinDown d = spin_down(s, w0, mu_t, 3);
    INFO("base radius " << base << ": first zero at " << d.stopped_at << " s (closed form "
                        << d.stop_time << " s), largest reversal " << d.most_reversed
                        << " rad/s, final " << d.final_spin);
    // The spring winds up over a few steps, then slips at the cap all the way.
    CHECK(std::abs(d.stopped_at - d.stop_time) <= 0.01 * d.stop_time);
    // The spring, wound to M_t, gives back at most its energy M_t^2 / (2 k_t): a
    // spin of M_t / sqrt(k_t I) = m g / sqrt(2.25 k_n I) (k_t = 2.25 k_n (mu_t R*)^2),
    // whatever mu_t and R*; the dashpot stills it.
    CHECK(d.most_reversed >= -(1 + 1e-6) * s.mass * g / std::sqrt(2.25 * k_normal * s.inertia));
    CHECK(std::abs(d.final_spin) <= 1e-4 * w0);
  }
}

TEST_CASE(
    "twisting: below the cap the epsd spring rings at sqrt(k_t / I) and its dashpot damps at eta_r",
    "[twisting]") {
  // A small twist on the floor (R* = r, I_t = I): the spring never reaches
  // M_t, so the spin rings at omega_t = sqrt(k_t / I), k_t = 2.25 k_n (mu_t r)^2
  // (the equality case of omega_t <= 2.37 mu_t omega_n), its amplitude
  // falling by exp(-eta_r omega_t t) with the dashpot 2 eta_r sqrt(I k_t).
  const double mu_t = 0.1;
  for (const double eta : {0.0, 0.05}) {
    const double w0 = 0.01;  // the cap's reversal spin is ~1 rad/s (test below)
    Spinner s = spinner({{"twisting_friction", mu_t}, {"rolling_damping", eta}}, w0);
    const double k_t = 2.25 * k_normal * (mu_t * s.r_star) * (mu_t * s.r_star);
    const double omega = std::sqrt(k_t / s.inertia);
    const double period = 2 * 3.141592653589793 / omega, dt = s.sim->time_step();
    // Upward zero crossings (interpolated) and the peaks between them.
    std::vector<double> crossings, peaks;
    double last = w0, peak = 0;
    const auto steps = static_cast<std::int64_t>(6.2 * period / dt);
    for (std::int64_t k = 0; k < steps; ++k) {
      s.sim->advance(1);
      const double w = s.sim->spin(s.id)[1];
      peak = std::max(peak, w);
      if (last < 0 && w >= 0) {
        crossings.push_back(s.sim->time() - dt * w / (w - last));
        peaks.push_back(peak);
        peak = 0;
      }
      last = w;
    }
    REQUIRE(crossings.size() >= 5);
    const double measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
    INFO("eta_r " << eta << ": period " << measured << " s, closed form " << period
                  << " s (undamped), " << period / dt << " steps");
    // The damped period is longer by 1 / sqrt(1 - eta^2).
    CHECK(measured == Approx(period / std::sqrt(1 - eta * eta)).epsilon(0.01));
    // Peak to peak over whole periods: exp(-eta omega T_d).
    const double periods = static_cast<double>(peaks.size() - 2);
    const double decay = peaks.back() / peaks[1];
    const double expected = std::exp(-eta * omega * periods * period / std::sqrt(1 - eta * eta));
    INFO("peaks " << peaks[1] << " -> " << peaks.back() << " over " << periods << " periods: ratio "
                  << decay << ", closed form " << expected);
    CHECK(decay == Approx(expected).epsilon(0.03));
  }
}

TEST_CASE("twisting: without twisting_friction a spin about the normal goes on", "[twisting]") {
  // Friction and the rolling torque act on the rolling, not the twist: the
  // control that shows the tests above measure the twisting torque.
  const double w0 = 50;
  for (const ParamValues& law :
       {ParamValues{}, ParamValues{{"rolling_friction", 0.1}, {"rolling_damping", 0.3}}}) {
    Spinner s = spinner(law, w0);
    s.sim->advance(static_cast<std::int64_t>(0.05 / s.sim->time_step()));
    CHECK(s.sim->spin(s.id)[1] == Approx(w0).epsilon(1e-9));
  }
}

TEST_CASE("twisting: a pair's twist is exchanged, its angular momentum kept", "[twisting]") {
  // Unequal spheres (radii 1:2, densities 1:3) strike head-on along x with
  // spins about x; no gravity, no walls. Twisting resistance moves angular
  // momentum between them along x: I_i w_i + I_j w_j stays, to round-off.
  for (const double model : {rolling_model::epsd, rolling_model::constant}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"a", density, 0, 0, 0});
    sim.add_material({"b", 3 * density, 0, 0, 0});
    const ParamValues law{{"k_normal", k_normal},
                          {"restitution", 0.9},
                          {"friction", 0.5},
                          {"twisting_friction", 0.3},
                          {"rolling_model", model}};
    for (const char* a : {"a", "b"})
      for (const char* b : {"a", "b"}) sim.set_contact(a, b, "linear", law);
    ParticleSpec i, j;
    i.radius = radius, i.material = 0, i.position = {-radius * 1.01, 0, 0};
    i.velocity = {0.05, 0, 0}, i.spin = {300, 0, 0};
    j.radius = 2 * radius, j.material = 1, j.position = {2 * radius * 1.01, 0, 0};
    j.velocity = {-0.05, 0, 0}, j.spin = {-100, 0, 0};
    const std::int64_t id_i = sim.add_particle(i), id_j = sim.add_particle(j);
    sim.prepare();
    const double inertia_i = sphere_inertia(sphere_mass(radius, density), radius);
    const double inertia_j = sphere_inertia(sphere_mass(2 * radius, 3 * density), 2 * radius);
    const double before = inertia_i * 300 - inertia_j * 100;
    sim.advance(static_cast<std::int64_t>(0.03 / sim.time_step()));
    REQUIRE(sim.stats().contacts_particle == 0);  // they struck and parted
    const double w_i = sim.spin(id_i)[0], w_j = sim.spin(id_j)[0];
    const double after = inertia_i * w_i + inertia_j * w_j;
    INFO("model " << model << ": spins " << w_i << ", " << w_j << " rad/s after; L_x " << before
                  << " -> " << after);
    CHECK(std::abs(after - before) <= 1e-12 * inertia_i * 300);
    CHECK(w_i < 300 - 1);  // the twist acted
    // Only about x: no other spin arose.
    CHECK(std::abs(sim.spin(id_i)[1]) + std::abs(sim.spin(id_i)[2]) <= 1e-9);
  }
}

TEST_CASE("twisting: twisting_friction is checked, chosen per pair and 3D only", "[twisting]") {
  Simulation<3> sim;
  sim.add_material({"p", density, 0, 0, 0});
  const ParamValues plain{{"k_normal", 1e3}, {"restitution", 1}};
  auto with = [&](ParamValues extra) {
    ParamValues law = plain;
    for (const auto& [k, v] : extra) law[k] = v;
    return law;
  };
  const int linear = contact_model_id("linear");
  // twisting_friction alone chooses the term; 0 alone is the plain law.
  sim.set_contact("p", "p", "linear", with({{"twisting_friction", 0.1}}));
  CHECK(sim.pair_table().at(0, 0).model == rolling_contact_model(linear));
  sim.set_contact("p", "p", "linear", with({{"twisting_friction", 0}}));
  CHECK(sim.pair_table().at(0, 0).model == linear);
  sim.set_contact("p", "p", "linear",
                  with({{"twisting_friction", 0}, {"rolling_friction", 0}, {"rolling_model", 1}}));
  CHECK(sim.pair_table().at(0, 0).model == linear);
  CHECK_THROWS_WITH(sim.set_contact("p", "p", "linear", with({{"twisting_friction", -0.1}})),
                    Catch::Contains("twisting_friction"));
  // A run may drop one torque while the other stays, not both.
  sim.set_contact("p", "p", "linear",
                  with({{"twisting_friction", 0.1}, {"rolling_friction", 0.2}}));
  sim.update_contact("p", "p", {{"rolling_friction", 0}});
  CHECK_THROWS_WITH(sim.update_contact("p", "p", {{"twisting_friction", 0}}),
                    Catch::Contains("twisting_friction") && Catch::Contains("must stay > 0"));
  // The plain law cannot take it during a run: the term is chosen at the declaration.
  sim.set_contact("p", "p", "linear", plain);
  CHECK_THROWS_WITH(sim.update_contact("p", "p", {{"twisting_friction", 0.1}}),
                    Catch::Contains("twisting_friction") && Catch::Contains("sim:contact"));

  // 2D spins are about z, normal to every contact normal: refused, not ignored.
  Simulation<2> flat;
  flat.add_material({"p", density, 0, 0, 0});
  CHECK_THROWS_WITH(flat.set_contact("p", "p", "linear", with({{"twisting_friction", 0.1}})),
                    Catch::Contains("twisting_friction") && Catch::Contains("3D only"));
  flat.set_contact("p", "p", "linear", with({{"rolling_friction", 0.1}, {"twisting_friction", 0}}));
  CHECK_THROWS_WITH(flat.update_contact("p", "p", {{"twisting_friction", 0.1}}),
                    Catch::Contains("3D only"));
}

TEST_CASE("twisting: the epsd twisting spring's own mode bounds the time step", "[twisting]") {
  // omega_t <= 2.37 mu_t omega_n (a sphere on a wall, I_t = 0.4 m R*^2).
  auto limit = [](double mu_t, double model) {
    Spinner s = spinner({{"twisting_friction", mu_t}, {"rolling_model", model}}, 0);
    return s.sim->time_step_rule().stability_limit;
  };
  const double plain = limit(0.3, rolling_model::epsd);  // ratio 0.71: the normal mode's
  CHECK(limit(2, rolling_model::epsd) == Approx(plain / (std::sqrt(2.25 / 0.4) * 2)));
  CHECK(limit(20, rolling_model::constant) == Approx(plain));
  CHECK_THROWS_WITH(limit(20, rolling_model::epsd),
                    Catch::Contains("stability limit") && Catch::Contains("twisting"));
}

TEST_CASE("twisting: a checkpoint of builds without the twisting torque restarts, no twist held",
          "[twisting][checkpoint]") {
  // Rolling springs wound on a pair (a sphere rolling on a fixed one) and on a
  // wall (one rolling on the floor); the histories then cut to the layout
  // builds before the twisting torque wrote, {base, rolling}.
  using Rolling = WithRolling<LinearSpringDashpot, rolling_names::linear>;
  using New = Rolling::History<3>;
  using Old = Rolling::HistoryWithoutTwisting<3>;
  static_assert(offsetof(New, twisting) == sizeof(Old));
  auto scene = [] {
    Spinner s = spinner({{"rolling_friction", 0.1}, {"rolling_damping", 0.3}}, 0, 3 * radius);
    s.sim->set_spin(s.id, {0, 0, 20});
    ParticleSpec p;
    p.radius = radius;
    p.material = 0;
    p.position = {20 * radius, radius - s.mass * g / k_normal, 0};
    p.velocity = {0.05, 0, 0};
    p.spin = {0, 0, -30};
    s.sim->add_particle(p);
    s.sim->prepare();
    return s;
  };
  Spinner whole = scene();
  whole.sim->advance(300);
  const StateBlob saved = whole.sim->save_state();
  whole.sim->advance(300);

  StateBlob old = saved;
  for (const std::string key : {"pairs.linear+rolling.", "walls.linear+rolling."}) {
    REQUIRE(old.integers.at(key + "layout").at(1) == static_cast<std::int64_t>(sizeof(New)));
    const std::vector<std::uint8_t>& records = saved.bytes.at(key + "history");
    REQUIRE(records.size() == sizeof(New));  // one contact each
    std::vector<std::uint8_t> cut;
    for (std::size_t at = 0; at < records.size(); at += sizeof(New)) {
      double twist, rolling[3];
      std::memcpy(&twist, &records[at + sizeof(Old)], sizeof twist);
      CHECK(twist == 0.0);  // mu_t = 0: nothing wound
      // The rolling spring was wound: the restart has a history to carry.
      std::memcpy(rolling, &records[at + offsetof(New, rolling)], sizeof rolling);
      CHECK(std::abs(rolling[0]) + std::abs(rolling[1]) + std::abs(rolling[2]) > 0);
      cut.insert(cut.end(), records.begin() + at, records.begin() + at + sizeof(Old));
    }
    old.bytes[key + "history"] = cut;
    old.integers[key + "layout"][1] = sizeof(Old);
  }
  // Nor did they say what their rolling springs held: the linear law's, M_k
  // either way, are taken as they are (though wound, as checked above).
  REQUIRE(old.integers.erase("rolling_springs") == 1);
  // Those builds' laws had no twisting_friction either.
  std::string& laws = old.texts.at("contacts");
  const std::string twist_entry = "\ttwisting_friction=0";
  REQUIRE(laws.find(twist_entry) != std::string::npos);
  for (std::size_t at; (at = laws.find(twist_entry)) != std::string::npos;)
    laws.erase(at, twist_entry.size());
  Spinner resumed = scene();
  resumed.sim->load_state(old);
  resumed.sim->advance(300);
  for (const std::int64_t id : {std::int64_t{1}, std::int64_t{2}}) {
    CHECK(resumed.sim->position(id) == whole.sim->position(id));
    CHECK(resumed.sim->spin(id) == whole.sim->spin(id));
  }

  // Another record size is refused by name.
  StateBlob other = saved;
  other.integers["pairs.linear+rolling.layout"][1] = sizeof(Old) - 8;
  Spinner refused = scene();
  CHECK_THROWS_WITH(refused.sim->load_state(other),
                    Catch::Contains("linear+rolling") && Catch::Contains("layout"));
}

TEST_CASE("twisting: a ringing normal load does not pump the twist (its energy is kept)",
          "[twisting]") {
  // A sphere on a floor, no damping anywhere, let go at half its resting
  // overlap so that the normal load rings; a small twist w0 with the spring
  // unloaded. With Hertz's k_n following the overlap, the twist's mode is
  // modulated at the normal frequency; at mu_t where that is twice the twist's
  // own (2.25 mu_t^2 / 0.4 = 1/4 of the normal stiffness ratio: 0.21 for
  // hertz_mindlin's tangent, 0.26 for thornton_elastic's secant, 1.5 N / delta)
  // a spring holding T was pumped to 0.71 and 0.86 rad/s over 0.1 s
  // (tools/twist_pump.lua, the same scene, with build c7d4ee6). Holding T / sqrt(k_t),
  // the twist's energy I w^2 / 2 + T^2 / (2 k_t) is kept, so |w| stays near w0.
  const double e = 1e8, nu = 0.3, w0 = 0.01;
  for (const auto& [model, mu_t] : {std::pair<const char*, double>{"hertz_mindlin", 0.211},
                                    std::pair<const char*, double>{"thornton_elastic", 0.258}}) {
    Simulation<3> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", density, e, nu, 0});
    sim.add_material({"w", 0, e, nu, 0});
    ParamValues law{{"friction", 0.3}, {"twisting_friction", mu_t}};
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
    const double rest = std::pow(3 * mass * g / (4 * e_star * std::sqrt(radius)), 2.0 / 3.0);
    ParticleSpec p;
    p.radius = radius;
    p.material = 0;
    p.position = {0, radius - 0.5 * rest, 0};
    p.spin = {0, w0, 0};
    const std::int64_t id = sim.add_particle(p);
    sim.prepare();
    double largest = 0, deepest = 0, shallowest = 1;
    const auto steps = static_cast<std::int64_t>(0.1 / sim.time_step());
    double first_half = 0;
    for (std::int64_t k = 0; k < steps; ++k) {
      sim.advance(1);
      largest = std::max(largest, std::abs(sim.spin(id)[1]));
      if (k == steps / 2) first_half = largest;
      const double overlap = radius - sim.position(id)[1];
      deepest = std::max(deepest, overlap), shallowest = std::min(shallowest, overlap);
    }
    INFO(model << ", mu_t " << mu_t << ": largest twist " << largest << " rad/s (" << first_half
               << " in the first half; w0 " << w0 << "), overlap " << shallowest / rest << "-"
               << deepest / rest << " of the rest");
    REQUIRE(shallowest > 0);        // it stayed on the floor
    REQUIRE(deepest > 1.3 * rest);  // and the normal load rang
    // Kept up to the step's exchange of spin and spring (|w| peaks a few per cent
    // above w0, staggered half a step from the torque), and not growing.
    CHECK(largest <= 1.1 * w0);
    CHECK(largest <= 1.001 * first_half);
  }
}
