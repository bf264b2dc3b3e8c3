// The Mechanofusion diagnostics (src/hooks/zones.hpp, areas.hpp,
// contact_peaks.hpp) against closed forms: the spherical-cap split of
// Eqs. 4.3-4.6 against quadrature, equal zone volumes summing to the
// chamber's, zero rotational energy for a set co-rotating with the chamber
// (4.10), the virial pressure (4.12) and collision work (4.13) of a known
// overlapping pair, the areas' forces and collision counts (4.14), and the
// peak force of a binary impact against F_max = v sqrt(m* K1) (7.2).
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/simulation.hpp"
#include "hooks/chamber_frame.hpp"
#include "hooks/zones.hpp"

using namespace granule;

namespace {
constexpr double R = 12.5e-3, r = 0.2e-3, rho = 1200, k1 = 2e4, e_r = 0.85;

// A chamber (radius R, spin omega) and, when wanted, an inner piece at +x.
void chamber(Simulation<2>& sim, double omega, bool inner = false) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  ParamValues law{{"k_load", k1}, {"restitution", e_r}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", law);
  sim.set_contact("powder", "steel", "walton_braun", law);
  WallSpec c;
  c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
  c.angular_velocity = omega;
  sim.add_wall(c);
  if (inner) {
    WallSpec in;
    in.name = "inner_piece", in.type = WallType::cylinder, in.material = 1, in.radius = 5e-3;
    in.center = {5.9e-3, 0, 0}, in.inside = false;
    sim.add_wall(in);
  }
}

int particle(Simulation<2>& sim, double x, double y, double vx = 0, double vy = 0,
             double spin = 0) {
  ParticleSpec s;
  s.position = {x, y, 0}, s.velocity = {vx, vy, 0}, s.spin = {0, 0, spin};
  s.radius = r, s.material = 0;
  return static_cast<int>(sim.add_particle(s));
}

int attach(Simulation<2>& sim, const char* name, DiagnosticOptions o) {
  return sim.attach_diagnostic(name, o);
}

// A pair pressed `delta` into each other in the input area (280 deg, about -80).
void pressed_pair_in_input(Simulation<2>& sim, double delta) {
  const double l = 9e-3, a = 280 * pi / 180;
  const double cx = l * std::cos(a), cy = l * std::sin(a);
  particle(sim, cx - (r - delta / 2), cy);
  particle(sim, cx + (r - delta / 2), cy);
}
}  // namespace

TEST_CASE("zones: the spherical-cap split (4.3-4.6) matches a quadrature of the sphere",
          "[diagnostics][mechanofusion]") {
  // Fraction of the sphere's volume with y < -a (a = l - b): slices pi (r^2 - y^2) dy.
  for (double a_over_r : {-1.0, -0.7, -0.2, 0.0, 0.3, 0.9, 1.0}) {
    const double a = a_over_r * r;
    const int n = 20000;
    double inside = 0;
    for (int k = 0; k < n; ++k) {
      const double y = -r + (k + 0.5) * 2 * r / n;
      if (y < -a) inside += pi * (r * r - y * y) * 2 * r / n;
    }
    const double total = 4.0 / 3.0 * pi * r * r * r;
    CHECK(zone_inner_fraction(5e-3 + a, 5e-3, r) == Approx(inside / total).margin(2e-4));
  }
  CHECK(zone_inner_fraction(5e-3, 5e-3, r) == Approx(0.5));  // centre on the boundary
}

TEST_CASE("zones: equal volumes that sum to the chamber's, each particle counted once",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  chamber(sim, 0);
  // Particles on and across zone boundaries, none touching.
  const double boundaries[] = {R * std::sqrt(1.0 / 7), R * std::sqrt(3.0 / 7),
                               R * std::sqrt(6.0 / 7)};
  int n = 0;
  for (double b : boundaries)
    for (double shift : {-0.15 * r, 0.0, 0.6 * r}) {
      const double angle = 0.7 * n++;
      particle(sim, (b + shift) * std::cos(angle), (b + shift) * std::sin(angle));
    }
  DiagnosticOptions o;
  const int id = attach(sim, "zones", o);
  sim.advance(1);
  const auto res = sim.diagnostic_results(id);
  const auto arr = sim.diagnostic_arrays(id);
  const double depth = 2 * r;  // one particle diameter (4.3.2)
  CHECK(res.at("depth") == Approx(depth));
  CHECK(res.at("chamber_volume") == Approx(pi * R * R * depth));
  CHECK(res.at("zone_volume_sum") == Approx(pi * R * R * depth).epsilon(1e-12));
  REQUIRE(arr.at("zone_volume").size() == 7);
  for (double v : arr.at("zone_volume")) CHECK(v == Approx(pi * R * R * depth / 7).epsilon(1e-12));
  // The fractions of every particle add up to one: the counts sum to n.
  double total = 0;
  for (double c : arr.at("count")) total += c;
  CHECK(total == Approx(n).epsilon(1e-12));
  CHECK(res.at("mean_particle_count") == Approx(n).epsilon(1e-12));
  // A particle centred on a boundary puts half of itself on each side: solid
  // fraction of the two zones = half a sphere each (plus the others' shares).
  double solid = 0;
  const auto& volume = arr.at("zone_volume");
  for (std::size_t z = 0; z < 7; ++z) solid += arr.at("solid_fraction")[z] * volume[z];
  CHECK(solid == Approx(n * 4.0 / 3.0 * pi * r * r * r).epsilon(1e-12));
}

TEST_CASE("zones: a set co-rotating with the chamber has no rotational energy (4.10)",
          "[diagnostics][mechanofusion]") {
  const double omega = 2000 * 2 * pi / 60;
  Simulation<2> sim;
  chamber(sim, omega);
  // A full ring at one radius, inside zone 3 (6.68 to 8.18 mm), moving and
  // spinning with the chamber.
  const double l = 7.4e-3;
  const int n = 24;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * pi * k / n;
    particle(sim, l * std::cos(a), l * std::sin(a), -omega * l * std::sin(a),
             omega * l * std::cos(a), omega);
  }
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  const int id = attach(sim, "zones", o);
  sim.advance(1);
  const auto arr = sim.diagnostic_arrays(id);
  const auto& volume = arr.at("zone_volume");
  for (double e : arr.at("rotational_ke")) CHECK(std::abs(e) < 1e-12);
  // Deviatoric energy about the polar mean: none (every particle moves at the
  // zone's mean azimuthal speed); about the Cartesian mean (zero for a ring),
  // all of the translational energy, as SPEC 4.2 warns.
  const int zone = static_cast<int>(7 * l * l / (R * R));
  const double m = sphere_mass(r, rho);
  for (double e : arr.at("deviatoric_ke")) CHECK(std::abs(e) < 1e-9);
  CHECK(arr.at("deviatoric_ke_cartesian")[zone] ==
        Approx(n * 0.5 * m * omega * omega * l * l / (2 * volume[zone]) * 2).epsilon(1e-9));
  // And a ring that does not spin has the chamber's spin as its rotational energy.
  Simulation<2> still;
  chamber(still, omega);
  for (int k = 0; k < n; ++k)
    particle(still, l * std::cos(2 * pi * k / n), l * std::sin(2 * pi * k / n));
  const int sid = attach(still, "zones", o);
  still.advance(1);
  const double inertia = sphere_inertia(m, r);
  CHECK(still.diagnostic_arrays(sid).at("rotational_ke")[zone] ==
        Approx(n * inertia * omega * omega / (2 * volume[zone])).epsilon(1e-12));
}

TEST_CASE("zones: virial pressure (4.12) and collision work (4.13) of a known pair",
          "[diagnostics][mechanofusion]") {
  const double delta = 2e-6, u = 0.05;  // overlap [m], each particle's approach speed [m/s]
  const double y = 5e-3;                // contact point at (0, y)
  Simulation<2> sim;
  chamber(sim, 0);
  particle(sim, -(r - delta / 2), y, u, 0);
  particle(sim, r - delta / 2, y, -u, 0);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.strings["mean"] = "cartesian";
  const int id = attach(sim, "zones", o);
  sim.advance(1);  // observed before the first integration: the set-up state
  const auto arr = sim.diagnostic_arrays(id);
  const int zone = static_cast<int>(7 * y * y / (R * R));
  const double vk = arr.at("zone_volume")[zone];
  const double normal = k1 * delta;  // Walton-Braun loading branch (3.1)
  CHECK(arr.at("pressure_virial")[zone] ==
        Approx(normal * (2 * r - delta) / (3 * vk)).epsilon(1e-9));
  // Kinetic part: m (v - v_mean)^2 summed, over 3 V (the pair's mean velocity is zero).
  const double m = sphere_mass(r, rho);
  CHECK(arr.at("pressure_kinetic")[zone] == Approx(2 * m * u * u / (3 * vk)).epsilon(1e-9));
  CHECK(arr.at("pressure")[zone] ==
        Approx(arr.at("pressure_kinetic")[zone] + arr.at("pressure_virial")[zone]));
  // 4.13 per unit time: N d(alpha)/dt with d(alpha)/dt = 2u at the velocities half a
  // step behind, brought to the step by half a step of each particle's N / m.
  CHECK(arr.at("collision_work_rate")[zone] ==
        Approx(normal * (2 * u - sim.time_step() * normal / m) / vk).epsilon(1e-9));
  for (int z = 0; z < 7; ++z)
    if (z != zone) CHECK(arr.at("pressure_virial")[z] == 0);
}

TEST_CASE("areas: forces per particle and per contact, collisions and their ratio (4.14)",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  chamber(sim, 0, true);
  // A resting overlapping pair in the input area (angle 280 deg, about -80).
  const double delta = 2e-6;
  pressed_pair_in_input(sim, delta);
  // A particle flying at the chamber wall in the scraper area (100 deg).
  const double b = 100 * pi / 180, gap = 1e-6, v = 0.2;
  const double lw = R - r - gap;
  particle(sim, lw * std::cos(b), lw * std::sin(b), v * std::cos(b), v * std::sin(b));
  // Two particles about to collide in the free-diffusion area (200 deg).
  const double c = 200 * pi / 180, lc = 8e-3;
  particle(sim, lc * std::cos(c) - r - gap, lc * std::sin(c), v, 0);
  particle(sim, lc * std::cos(c) + r + gap, lc * std::sin(c), -v, 0);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.numbers["window"] = 1;
  const int id = attach(sim, "areas", o);
  sim.advance(1);
  auto res = sim.diagnostic_results(id);
  const double normal = k1 * delta;
  // Input area: two particles, each pressed by N; one particle-particle contact.
  CHECK(res.at("particles_input") == 2);
  CHECK(res.at("normal_force_per_particle_input") == Approx(normal).epsilon(1e-9));
  CHECK(res.at("normal_force_per_contact_input") == Approx(normal).epsilon(1e-9));
  CHECK(res.at("tangential_force_per_contact_input") == 0);
  // The pair was pressed together before the diagnostic saw a step: no collision of its.
  CHECK(res.at("collisions_particle_input") == 0);
  CHECK(res.at("collision_ratio_particle_input") == 0);
  CHECK(res.at("particles_inner_piece") == 0);
  // Run until the flying ones have hit: one boundary collision in the scraper
  // area, one particle collision in the free-diffusion area.
  sim.advance(static_cast<std::int64_t>(2 * gap / v / sim.time_step()) + 10);
  res = sim.diagnostic_results(id);
  CHECK(res.at("collisions_boundary_scraper") == 1);
  CHECK(res.at("collisions_particle_free_diffusion") == 1);
  CHECK(res.at("collisions_boundary_free_diffusion") == 0);
  CHECK(res.at("collision_ratio_boundary_scraper") == Approx(1.0));
  CHECK(res.at("collision_ratio_particle_free_diffusion") == Approx(0.5));
}

TEST_CASE("areas: contacts going on when it is attached are no collisions, later ones are",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  chamber(sim, 0, true);
  // A pair pressed together in the input area, stepped before the diagnostic comes.
  const double delta = 2e-6;
  pressed_pair_in_input(sim, delta);
  // Two particles that meet after it is attached, in the free-diffusion area.
  const double c = 200 * pi / 180, lc = 8e-3, gap = 2e-6, v = 0.2;
  particle(sim, lc * std::cos(c) - r - gap, lc * std::sin(c), v, 0);
  particle(sim, lc * std::cos(c) + r + gap, lc * std::sin(c), -v, 0);
  sim.advance(3);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.numbers["window"] = 1;
  const int id = attach(sim, "areas", o);
  sim.advance(static_cast<std::int64_t>(2 * gap / v / sim.time_step()) + 10);
  auto res = sim.diagnostic_results(id);
  CHECK(res.at("particles_input") == 2);  // still pressed together, but no new collision
  CHECK(res.at("collisions_particle_input") == 0);
  CHECK(res.at("collisions_particle_free_diffusion") == 1);
}

TEST_CASE("areas: a polyline's contact going on when it is attached is no collision",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  chamber(sim, 0, true);
  // A short polyline across the input area (280 deg), a particle pressed into it,
  // and one that reaches it after the attach.
  const double l = 9e-3, a = 280 * pi / 180, delta = 2e-6, gap = 2e-6, v = 0.2;
  const double cx = l * std::cos(a), cy = l * std::sin(a);
  PolylineWallSpec bar;
  bar.name = "bar", bar.material = 1;
  bar.points = {{cx - 2e-3, cy}, {cx + 2e-3, cy}};
  sim.add_polyline_wall(bar);
  particle(sim, cx - 1e-3, cy + (r - delta));
  particle(sim, cx + 1e-3, cy + r + gap, 0, -v);
  sim.advance(3);
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.numbers["window"] = 1;
  const int id = attach(sim, "areas", o);
  sim.advance(static_cast<std::int64_t>(gap / v / sim.time_step()) + 10);
  const auto res = sim.diagnostic_results(id);
  CHECK(res.at("particles_input") == 2);
  CHECK(res.at("collisions_boundary_input") == 1);  // the second particle's only
}

TEST_CASE("areas: sectors count from the inner piece and must not overlap",
          "[diagnostics][mechanofusion]") {
  AreaSectors s;
  DiagnosticOptions o;
  s.read(o);
  CHECK(s.area_of(0) == 0);
  CHECK(s.area_of(350) == 0);  // -10 deg: the converging side of the gap
  CHECK(s.area_of(100) == 1);
  CHECK(s.area_of(300) == 2);
  CHECK(s.area_of(200) == 3);
  DiagnosticOptions bad;
  bad.lists["area_scraper"] = {40, 150};
  CHECK_THROWS_WITH(s.read(bad), Catch::Contains("overlap"));
  DiagnosticOptions backwards;
  backwards.lists["area_input"] = {300, 250};
  CHECK_THROWS_WITH(s.read(backwards), Catch::Contains("area_input"));
}

TEST_CASE("contact_peaks: a binary impact's peak force, derived velocity and coating area",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  chamber(sim, 0);
  const double v = 0.5, gap = 1e-6, x = 3e-3;  // in the inner-piece area (angles from +x)
  particle(sim, x - r - gap, 0, v / 2, 0);
  particle(sim, x + r + gap, 0, -v / 2, 0);
  const double m_eff = 0.5 * sphere_mass(r, rho);
  DiagnosticOptions o;
  o.strings["inner_piece"] = "";
  o.numbers["force_per_velocity"] = std::sqrt(m_eff * k1);  // 7.2's c for the loading spring
  o.numbers["keep_collisions"] = 10;
  const int id = attach(sim, "contact_peaks", o);
  sim.advance(20000);
  const auto res = sim.diagnostic_results(id);
  const auto arr = sim.diagnostic_arrays(id);
  REQUIRE(res.at("contacts_all") == 1);
  CHECK(res.at("contacts_inner_piece") == 1);
  // Peak force on the loading spring: v sqrt(m* K1) (energy balance), so the
  // derived velocity F_max / c is the impact speed.
  const double f_max = v * std::sqrt(m_eff * k1);
  CHECK(res.at("mean_peak_force_all") == Approx(f_max).epsilon(0.02));
  const auto& vh = arr.at("velocity_hist_all");
  const auto& edges = arr.at("velocity_edges");
  for (std::size_t k = 0; k < vh.size(); ++k)
    if (vh[k] > 0) CHECK((edges[k] <= v * 1.02 && edges[k + 1] >= v * 0.98));
  CHECK(res.at("fraction_over_200_mm_s_all") == 1);
  CHECK(res.at("fraction_over_1000_mm_s_all") == 0);
  // 4.7: one host-host contact adds pi d R* to the covered area, d = v sqrt(m*/K1).
  const double d = v * std::sqrt(m_eff / k1);
  CHECK(res.at("covered_fraction") == Approx(pi * d * r / 2 / (2 * 4 * pi * r * r)).epsilon(0.03));
  REQUIRE(arr.at("collision_overlap").size() == 1);
  CHECK(arr.at("collision_overlap")[0] == Approx(d).epsilon(0.02));
  CHECK(arr.at("collision_radius")[0] == Approx(r / 2));
  CHECK(res.at("coating_reached") == 0);
  // The readings of 4.7 on this one collision: two patches double it, and so does
  // R = r (= 2 R* for equal hosts); both, four times.
  const double one = res.at("covered_fraction");
  CHECK(res.at("covered_fraction_one_patch_rstar") == Approx(one).epsilon(1e-12));
  CHECK(res.at("covered_fraction_two_patches_rstar") == Approx(2 * one).epsilon(1e-12));
  CHECK(res.at("covered_fraction_one_patch_r") == Approx(2 * one).epsilon(1e-12));
  CHECK(res.at("covered_fraction_two_patches_r") == Approx(4 * one).epsilon(1e-12));
}

TEST_CASE(
    "contact_peaks: a collision going on when it is attached is not counted, whatever was "
    "attached before it",
    "[diagnostics][mechanofusion]") {
  // The engine marks the contacts going on only when the first diagnostic that
  // follows contacts is attached: here `areas`, before the impact. contact_peaks,
  // attached in the middle of the impact, must leave it out all the same.
  for (const bool areas_first : {false, true}) {
    Simulation<2> sim;
    chamber(sim, 0);
    const double v = 0.5, gap = 1e-6, x = 3e-3;
    particle(sim, x - r - gap, 0, v / 2, 0);
    particle(sim, x + r + gap, 0, -v / 2, 0);
    DiagnosticOptions o;
    o.strings["inner_piece"] = "";
    if (areas_first) attach(sim, "areas", o);
    // Into the impact, a few steps past its start.
    std::int64_t steps = 0;
    while (sim.stats().contacts_particle == 0 && steps < 100000) sim.advance(1), ++steps;
    sim.advance(3);
    REQUIRE(sim.stats().contacts_particle == 1);
    const int id = attach(sim, "contact_peaks", o);
    sim.advance(20000);
    INFO("areas attached first: " << areas_first);
    CHECK(sim.stats().contacts_particle == 0);
    CHECK(sim.diagnostic_results(id).at("contacts_all") == 0);
  }
}

TEST_CASE("contact_peaks: the coating readings of 4.7 on unequal hosts, counted by hand",
          "[diagnostics][mechanofusion]") {
  // Pairs of radii r and r/2 colliding at three speeds, each far from the others:
  // every collision adds pi d R* (one patch), 2 pi d R*, pi d (r + r/2) / 2 and
  // pi d (r + r/2), with d the kept peak overlap; the target is the moving hosts'
  // surface sum 4 pi r_i^2.
  Simulation<2> sim;
  chamber(sim, 0);
  const double gap = 1e-6, small = r / 2;
  int placed = 0;
  for (double v : {0.2, 0.5, 1.0}) {
    const double y = -4e-3 + 4e-3 * placed++;
    ParticleSpec a, b;
    a.position = {-r - gap, y, 0}, a.velocity = {v / 2, 0, 0}, a.radius = r, a.material = 0;
    b.position = {small + gap, y, 0}, b.velocity = {-v / 2, 0, 0}, b.radius = small, b.material = 0;
    sim.add_particle(a);
    sim.add_particle(b);
  }
  DiagnosticOptions o;
  o.strings["inner_piece"] = "";
  o.numbers["keep_collisions"] = 10;
  const int id = attach(sim, "contact_peaks", o);
  sim.advance(20000);
  const auto res = sim.diagnostic_results(id);
  const auto arr = sim.diagnostic_arrays(id);
  REQUIRE(arr.at("collision_overlap").size() == 3);
  const double target = 3 * 4 * pi * (r * r + small * small);
  double by_rstar = 0, by_r = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(arr.at("collision_radius")[k] == Approx(r * small / (r + small)));
    by_rstar += pi * arr.at("collision_overlap")[k] * arr.at("collision_radius")[k];
    by_r += pi * arr.at("collision_overlap")[k] * (r + small) / 2;
  }
  CHECK(res.at("covered_fraction_one_patch_rstar") == Approx(by_rstar / target).epsilon(1e-12));
  CHECK(res.at("covered_fraction_two_patches_rstar") ==
        Approx(2 * by_rstar / target).epsilon(1e-12));
  CHECK(res.at("covered_fraction_one_patch_r") == Approx(by_r / target).epsilon(1e-12));
  CHECK(res.at("covered_fraction_two_patches_r") == Approx(2 * by_r / target).epsilon(1e-12));
  CHECK(res.at("coating_time_two_patches_r") == 0);  // far from covered: not reached
}

TEST_CASE("zones: in 3D the depth is the slab's and spin about x and y counts in full (4.10)",
          "[diagnostics][mechanofusion]") {
  const double omega = 100;
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  sim.set_contact("powder", "steel", "walton_braun", {{"k_load", k1}, {"restitution", e_r}});
  sim.set_contact("powder", "powder", "walton_braun", {{"k_load", k1}, {"restitution", e_r}});
  WallSpec c;
  c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
  c.angular_velocity = omega;
  sim.add_wall(c);
  ParticleSpec s;
  s.position = {5.5e-3, 0, 0.8e-3}, s.spin = {3, 4, omega}, s.radius = r, s.material = 0;
  sim.add_particle(s);
  DiagnosticOptions missing;
  CHECK_THROWS_WITH(sim.attach_diagnostic("zones", missing), Catch::Contains("depth"));
  DiagnosticOptions o;
  o.numbers["depth"] = 1.6e-3;
  o.numbers["every"] = 1;
  const int id = sim.attach_diagnostic("zones", o);
  sim.advance(1);
  const auto arr = sim.diagnostic_arrays(id);
  CHECK(sim.diagnostic_results(id).at("chamber_volume") == Approx(pi * R * R * 1.6e-3));
  const int zone = static_cast<int>(7 * 5.5e-3 * 5.5e-3 / (R * R));
  const double inertia = sphere_inertia(sphere_mass(r, rho), r);
  // (w_x^2 + w_y^2 + (w_z - omega)^2) = 9 + 16 + 0
  CHECK(arr.at("rotational_ke")[zone] ==
        Approx(inertia * 25 / (2 * arr.at("zone_volume")[zone])).epsilon(1e-12));
}

// Eq. 4.13 summed over an impact is the energy the contact took: none for an
// elastic one, the kinetic energy lost for a damped one. With the overlap rate
// of leap-frog's lagging velocities an elastic impact on the chamber's wall
// "did" 8.8 % of its energy at 40 steps per contact.
TEST_CASE("zones: the collision work (4.13) of an impact is the energy it takes",
          "[diagnostics][mechanofusion]") {
  for (const double restitution : {1.0, 0.7}) {
    Simulation<2> sim;
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"powder", rho, 0, 0, 0});
    sim.add_material({"steel", 7800, 0, 0, 0});
    ParamValues law{{"k_normal", 1e3}, {"restitution", restitution}};
    sim.set_contact("powder", "powder", "linear", law);
    sim.set_contact("powder", "steel", "linear", law);
    WallSpec c;
    c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
    sim.add_wall(c);
    const double v0 = 0.5;
    particle(sim, R - r - 1e-6, 0, v0, 0);
    DiagnosticOptions o;
    o.numbers["every"] = 1;
    o.numbers["zones"] = 3;
    const int id = attach(sim, "zones", o);
    const double m = sphere_mass(r, rho), energy = 0.5 * m * v0 * v0;
    bool touched = false;
    std::int64_t steps = 0;
    for (; steps < 100000; ++steps) {
      sim.advance(1);
      const bool touching = sim.stats().contacts_wall > 0;
      if (touched && !touching) break;
      touched = touched || touching;
    }
    REQUIRE(touched);
    // The arrays are the run's means over its samples, one a step: times the run's
    // length, the integral over the impact.
    const auto arr = sim.diagnostic_arrays(id);
    double work = 0;
    for (std::size_t z = 0; z < arr.at("zone_volume").size(); ++z)
      work += arr.at("collision_work_rate")[z] * arr.at("zone_volume")[z] *
              static_cast<double>(sim.step_count()) * sim.time_step();
    const double lost = energy - sim.stats().kinetic_translational;
    INFO("e = " << restitution << ": work " << work << " J, kinetic energy lost " << lost
                << " J of " << energy);
    CHECK(std::abs(work - lost) < 2e-3 * energy);
  }
}

// A particle at rest on the chamber's wall under gravity does no collision work:
// half a step of its acceleration counts the weight integration adds, or its
// steady contact "worked" at N g dt / 2.
TEST_CASE("zones: a particle resting under gravity does no collision work (4.13)",
          "[diagnostics][mechanofusion]") {
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", rho, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  ParamValues law{{"k_normal", 1e3}, {"restitution", 0.3}};
  sim.set_contact("powder", "powder", "linear", law);
  sim.set_contact("powder", "steel", "linear", law);
  WallSpec c;
  c.name = "chamber", c.type = WallType::cylinder, c.material = 1, c.radius = R;
  sim.add_wall(c);
  const double g = 9.81, m = sphere_mass(r, rho);
  sim.set_gravity({0, -g, 0});
  particle(sim, 0, -(R - r));
  sim.advance(20000);  // settled
  DiagnosticOptions o;
  o.numbers["every"] = 1;
  o.numbers["zones"] = 3;
  const int id = attach(sim, "zones", o);
  sim.advance(1000);
  const auto arr = sim.diagnostic_arrays(id);
  double rate = 0;  // W, summed over the zones
  for (std::size_t z = 0; z < arr.at("zone_volume").size(); ++z)
    rate += arr.at("collision_work_rate")[z] * arr.at("zone_volume")[z];
  const double bias = m * g * g * sim.time_step() / 2;  // N g dt / 2 with N = m g
  INFO("rate " << rate << " W against the weightless estimate's bias " << bias << " W");
  CHECK(std::abs(rate) < 1e-3 * bias);
}
