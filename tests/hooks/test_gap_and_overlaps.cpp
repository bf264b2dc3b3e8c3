// The gap_profile diagnostic (src/hooks/gap_profile.hpp) against the closed
// form of a uniform shear between the chamber wall and the inner piece (the
// simple shear flow of Eqs. 5.2-5.6): the shear rate recovered exactly, a
// known granular temperature, the sector's volume against a grid count, the
// force per contact of a known pair; and the overlaps diagnostic
// (src/hooks/overlaps.hpp) on hand-placed overlaps of each kind.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double R = 12.5e-3, rho = 1200, k1 = 2e4;
constexpr double inner_x = 5.9e-3, inner_r = 5e-3;  // narrowest gap 1.6 mm at +x

void machine(Simulation<2>& sim, double omega) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  ParamValues law{{"k_load", k1}, {"restitution", 0.85}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", law);
  sim.set_contact("powder", "steel", "walton_braun", law);
  WallSpec c;
  c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
  c.angular_velocity = omega;
  sim.add_wall(c);
  WallSpec in;
  in.name = "inner_piece", in.type = WallType::cylinder, in.material = 1, in.radius = inner_r;
  in.center = {inner_x, 0, 0}, in.inside = false;
  sim.add_wall(in);
}

// Local gap along the ray at angle theta from +x (the inner piece's direction).
double local_gap(double theta) {
  const double s = inner_x * std::sin(theta);
  return R - (inner_x * std::cos(theta) + std::sqrt(inner_r * inner_r - s * s));
}

// Particles of radius rp at distance y from the chamber wall and angles +-theta,
// moving azimuthally at u(y) and radially at +-du (the + at +theta).
struct Placed {
  int count = 0;
  double volume = 0;
};
Placed shear_set(Simulation<2>& sim, double rp, double u0, double rate, double du) {
  Placed out;
  for (double y = 0.15e-3; y < 1.5e-3; y += 0.13e-3)
    for (double deg = 0.6; deg < 9.5; deg += 1.4)
      for (double sign : {1.0, -1.0}) {
        const double a = sign * deg * pi / 180, l = R - y;
        const double ut = u0 - rate * y, ur = sign * du;
        ParticleSpec s;
        s.position = {l * std::cos(a), l * std::sin(a), 0};
        s.velocity = {ur * std::cos(a) - ut * std::sin(a), ur * std::sin(a) + ut * std::cos(a), 0};
        s.radius = rp, s.material = 0;
        sim.add_particle(s);
        ++out.count;
        out.volume += 4.0 / 3.0 * pi * rp * rp * rp;
      }
  return out;
}
}  // namespace

TEST_CASE("gap_profile: a uniform shear across the gap has the shear rate it was given",
          "[diagnostics][mechanofusion]") {
  const double omega = 2000 * 2 * pi / 60, rp = 0.05e-3;
  const double rate = 1500;  // 1/s, of the order of omega R / H
  Simulation<2> sim;
  machine(sim, omega);
  const Placed set = shear_set(sim, rp, omega * R, rate, 0);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.numbers["sector"] = 10;
  o.numbers["bins"] = 5;
  const int id = sim.attach_diagnostic("gap_profile", o);
  sim.advance(1);  // observed before the first integration: the placed state
  const auto res = sim.diagnostic_results(id);
  CHECK(res.at("shear_rate") == Approx(rate).epsilon(1e-9));
  CHECK(res.at("nominal_shear_rate") == Approx(omega * R / 1.6e-3).epsilon(1e-12));
  CHECK(res.at("narrowest_gap") == Approx(1.6e-3).epsilon(1e-12));
  CHECK(res.at("particles") == set.count);
  // A linear profile carries no temperature, even within a bin's width.
  CHECK(res.at("mean_granular_temperature") < 1e-12 * omega * R * omega * R);
  // The profile is the linear one: each bin's mean speed decreases inward.
  const auto arr = sim.diagnostic_arrays(id);
  const auto& u = arr.at("azimuthal_velocity");
  for (std::size_t k = 1; k < u.size(); ++k)
    if (arr.at("count")[k] > 0 && arr.at("count")[k - 1] > 0) CHECK(u[k] < u[k - 1]);
  double counted = 0;
  for (double c : arr.at("count")) counted += c;
  CHECK(counted == set.count);
  // The sector's volume (depth one diameter in 2D) against a grid count of
  // the region between the wall and the inner piece within +-10 degrees.
  double grid_area = 0;
  const double step = 2e-6;
  for (double x = 10e-3; x < R; x += step)
    for (double y = -3e-3; y < 3e-3; y += step) {
      const double cx = x + step / 2, cy = y + step / 2;
      const double l = std::hypot(cx, cy), a = std::atan2(cy, cx);
      if (l < R && std::abs(a) <= 10 * pi / 180 && std::hypot(cx - inner_x, cy) > inner_r)
        grid_area += step * step;
    }
  double volume = 0;
  for (double v : arr.at("bin_volume")) volume += v;
  CHECK(volume == Approx(grid_area * 2 * rp).epsilon(2e-3));
  CHECK(res.at("mean_solid_fraction") == Approx(set.volume / volume).epsilon(1e-12));
  // The mean local gap of the sector lies between its centre's and its edge's.
  CHECK(res.at("mean_gap") > local_gap(0));
  CHECK(res.at("mean_gap") < local_gap(10 * pi / 180));
}

// In 2D the bins are one mean diameter of the moving particles deep, as the
// zones diagnostic's (4.3.2), whichever particle is stored first: a large one
// outside the sector used to set the depth alone (5 times the sector's).
TEST_CASE("gap_profile: in 2D the depth is the moving particles' mean diameter",
          "[diagnostics][mechanofusion]") {
  const double omega = 2000 * 2 * pi / 60, rp = 0.05e-3, big = 0.5e-3;
  auto sector_volume = [&](bool with_big, double& diameter) {
    Simulation<2> sim;
    machine(sim, omega);
    if (with_big) {
      ParticleSpec s;
      s.position = {-8e-3, 0, 0}, s.radius = big, s.material = 0;
      sim.add_particle(s);
    }
    shear_set(sim, rp, omega * R, 1500, 0);
    DiagnosticOptions o;
    o.numbers["every"] = 1;
    const int id = sim.attach_diagnostic("gap_profile", o);
    for (const auto& [name, value] : sim.diagnostic_results(id)) {
      INFO(name << " before the first sample");
      CHECK(std::isfinite(value));
    }
    sim.advance(1);
    diameter = sim.diagnostic_results(id).at("diameter");
    double volume = 0;
    for (double v : sim.diagnostic_arrays(id).at("bin_volume")) volume += v;
    return volume;
  };
  double plain_d = 0, mixed_d = 0;
  const double plain = sector_volume(false, plain_d), mixed = sector_volume(true, mixed_d);
  const Placed counted = [&] {
    Simulation<2> sim;
    machine(sim, omega);
    return shear_set(sim, rp, omega * R, 1500, 0);
  }();
  const double mean = (counted.count * 2 * rp + 2 * big) / (counted.count + 1);
  CHECK(plain_d == Approx(2 * rp).epsilon(1e-12));
  CHECK(mixed_d == Approx(mean).epsilon(1e-12));
  CHECK(mixed / plain == Approx(mean / (2 * rp)).epsilon(1e-12));
}

TEST_CASE("gap_profile: a known fluctuation is the granular temperature, per component",
          "[diagnostics][mechanofusion]") {
  const double omega = 1000 * 2 * pi / 60, rp = 0.05e-3, du = 0.3;
  Simulation<2> sim;
  machine(sim, omega);
  shear_set(sim, rp, omega * R, 800, du);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  const int id = sim.attach_diagnostic("gap_profile", o);
  sim.advance(1);
  // Radial +-du in equal numbers per bin (the pairs at +-theta share their
  // bin), the azimuthal part linear: T = <|v - u|^2> / 2 = du^2 / 2.
  CHECK(sim.diagnostic_results(id).at("mean_granular_temperature") ==
        Approx(du * du / 2).epsilon(1e-9));
  CHECK(sim.diagnostic_results(id).at("shear_rate") == Approx(800).epsilon(1e-9));
  const auto arrays = sim.diagnostic_arrays(id);
  const auto& count = arrays.at("count");
  for (std::size_t k = 0; k < count.size(); ++k)
    if (count[k] > 0)
      CHECK(arrays.at("granular_temperature")[k] == Approx(du * du / 2).epsilon(1e-9));
}

TEST_CASE("gap_profile: force per particle-particle contact in the sector only",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  machine(sim, 0);
  const double r = 0.2e-3, delta = 2e-6;
  auto pair = [&](double angle_deg, double l) {
    const double a = angle_deg * pi / 180;
    for (double side : {-1.0, 1.0}) {
      ParticleSpec s;
      const double along = side * (r - delta / 2);  // the pair lies along the tangent
      s.position = {l * std::cos(a) - along * std::sin(a), l * std::sin(a) + along * std::cos(a),
                    0};
      s.radius = r, s.material = 0;
      sim.add_particle(s);
    }
  };
  pair(0, R - 0.8e-3);   // in the gap
  pair(30, R - 0.8e-3);  // outside +-10 degrees
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  const int id = sim.attach_diagnostic("gap_profile", o);
  sim.advance(1);
  const auto res = sim.diagnostic_results(id);
  CHECK(res.at("contacts") == 1);
  CHECK(res.at("normal_force_per_contact") == Approx(k1 * delta).epsilon(1e-9));
  CHECK(res.at("particles") == 2);
}

TEST_CASE("gap_profile: a sector wider than the inner piece or a misplaced piece is refused",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  machine(sim, 0);
  ParticleSpec s;
  s.position = {12e-3, 0, 0}, s.radius = 0.2e-3, s.material = 0;
  sim.add_particle(s);
  DiagnosticOptions wide;
  wide.numbers["sector"] = 60;  // the inner piece spans asin(5 / 5.9) = 57.9 deg
  sim.attach_diagnostic("gap_profile", wide);
  CHECK_THROWS_WITH(sim.advance(1), Catch::Contains("sector 60 deg") && Catch::Contains("57.9"));
  DiagnosticOptions zero;
  zero.numbers["sector"] = 0;
  Simulation<2> other;
  machine(other, 0);
  CHECK_THROWS_WITH(other.attach_diagnostic("gap_profile", zero), Catch::Contains("sector"));
}

TEST_CASE("overlaps: the deepest contact of each kind, kept after it has relaxed",
          "[diagnostics]") {
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  ParamValues law{{"k_load", k1}, {"restitution", 0.85}, {"friction", 0}};
  sim.set_contact("powder", "powder", "walton_braun", law);
  WallSpec floor;
  floor.name = "floor", floor.type = WallType::plane, floor.material = 0;
  floor.normal = {0, 1, 0};
  sim.add_wall(floor);
  const double r = 1e-3, small = 0.5e-3;
  auto add = [&](double x, double y, double radius, bool fixed) {
    ParticleSpec s;
    s.position = {x, y, 0}, s.radius = radius, s.material = 0, s.fixed = fixed;
    return sim.add_particle(s);
  };
  // A pair (radii 1 and 0.5 mm) overlapping by 1 % of the smaller radius.
  add(0, 5e-3, r, false);
  add(r + small - 0.01 * small, 5e-3, small, false);
  // A moving particle pressed 2 % of its radius into a fixed one.
  add(10e-3, 5e-3, r, true);
  add(10e-3 + 2 * r - 0.02 * r, 5e-3, r, false);
  // A particle 3 % of its radius into the floor: the deepest.
  const auto deep = add(20e-3, r - 0.03 * r, r, false);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  const int id = sim.attach_diagnostic("overlaps", o);
  sim.advance(1);
  auto res = sim.diagnostic_results(id);
  CHECK(res.at("max_overlap_ratio_particle") == Approx(0.01).epsilon(1e-6));
  CHECK(res.at("max_overlap_ratio_fixed") == Approx(0.02).epsilon(1e-6));
  CHECK(res.at("max_overlap_ratio_wall") == Approx(0.03).epsilon(1e-6));
  CHECK(res.at("max_overlap_ratio") == Approx(0.03).epsilon(1e-6));
  CHECK(res.at("deepest_kind") == 2);
  CHECK(res.at("deepest_particle") == deep);
  CHECK(res.at("deepest_x") == Approx(20e-3));
  // The contacts push apart and end; the largest values stay.
  sim.advance(2000);
  CHECK(sim.stats().max_overlap_ratio < 0.005);
  res = sim.diagnostic_results(id);
  CHECK(res.at("max_overlap_ratio_wall") == Approx(0.03).epsilon(1e-6));
  CHECK(res.at("samples") == 2001);
}

TEST_CASE("overlaps: a collision's peak is exact even between samples", "[diagnostics]") {
  // Two equal spheres meeting at v: the Walton-Braun loading spring stops them at
  // d = v sqrt(m* / K1); samples every 100000 steps never see the contact.
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  ParamValues law{{"k_load", k1}, {"restitution", 0.85}, {"friction", 0}};
  sim.set_contact("powder", "powder", "walton_braun", law);
  const double r = 0.2e-3, v = 0.5, gap = 1e-6;
  for (double side : {-1.0, 1.0}) {
    ParticleSpec s;
    s.position = {side * (r + gap), 0, 0}, s.velocity = {-side * v / 2, 0, 0};
    s.radius = r, s.material = 0;
    sim.add_particle(s);
  }
  DiagnosticOptions o;
  o.numbers["every"] = 100000;
  const int id = sim.attach_diagnostic("overlaps", o);
  sim.advance(20000);
  const double m_eff = 0.5 * sphere_mass(r, rho);
  const auto res = sim.diagnostic_results(id);
  CHECK(res.at("max_overlap_ratio_particle") ==
        Approx(v * std::sqrt(m_eff / k1) / r).epsilon(0.02));
  CHECK(res.at("max_overlap_ratio_wall") == 0);
  CHECK(res.at("samples") == 1);
}
