// Walton-Braun partially latching spring with incrementally slipping friction
// (dissertation 3.3): closed forms of Eqs. 3.1-3.3 and Eq. 4.1.
#include <catch2/catch.hpp>

#include "contact/walton_braun.hpp"
#include "impact_helpers.hpp"

using namespace granule;
using granule::test::ImpactSetup;
using granule::test::run_impact;

namespace {
ParamValues table_3_1(double friction = 0.4) {
  return {{"k_load", 20000},
          {"restitution", 0.85},
          {"friction", friction},
          {"tangential_ratio", 0.8},
          {"slip_exponent", 1}};
}
const Material any_material{"m", 1000, 0, 0, 0};
WaltonBraun::Params params(const ParamValues& v) {
  return WaltonBraun::make(v, {any_material, any_material});
}
}  // namespace

TEMPLATE_TEST_CASE_SIG(
    "walton_braun: restitution is sqrt(K1/K2) (Eq. 3.1) and the force lasts "
    "(pi/2)(sqrt(m*/K1)+sqrt(m*/K2))",
    "[walton_braun]", ((int D), D), 2, 3) {
  const double k1 = 20000, e = GENERATE(0.5, 0.85, 0.95);
  const double r = 0.2e-3, rho = 1200;
  const double m = sphere_mass(r, rho);
  for (bool wall : {false, true}) {
    for (double v : {0.05, 0.5, 2.0}) {
      ImpactSetup s;
      s.params = {{"k_load", k1}, {"restitution", e}, {"friction", 0.4}};
      s.velocity = v;
      s.wall = wall;
      s.steps_per_contact = 400;  // discretisation error O(1/n)
      auto res = run_impact<D>(s);
      const double m_eff = wall ? m : m / 2;
      const double k2 = k1 / (e * e);
      const double duration = 0.5 * pi * (std::sqrt(m_eff / k1) + std::sqrt(m_eff / k2));
      INFO("D=" << D << " wall=" << wall << " v=" << v << " e=" << e);
      CHECK(res.restitution == Approx(e).epsilon(0.005));
      CHECK(res.force_duration == Approx(duration).epsilon(0.01));
      // Loading along K1 alone: max overlap v sqrt(m*/K1), max force K1 times that.
      CHECK(res.max_overlap == Approx(v * std::sqrt(m_eff / k1)).epsilon(0.005));
    }
  }
}

TEST_CASE("walton_braun: the default n = 40 keeps the restitution within 3%", "[walton_braun]") {
  ImpactSetup s;
  s.params = table_3_1();
  auto res = run_impact<2>(s);
  CHECK(res.restitution == Approx(0.85).epsilon(0.03));
}

TEST_CASE("walton_braun: partially latching normal force (Eq. 3.2)", "[walton_braun]") {
  auto p = params(table_3_1());
  const double k1 = p.k_load, k2 = p.k_unload;
  REQUIRE(k2 == Approx(k1 / (0.85 * 0.85)));
  WaltonBraun::History<2> h;
  auto c = test::state<2>(Eigen::Vector2d(1, 0), 0, Eigen::Vector2d::Zero(), 1e-6);
  auto at = [&](double a) {
    c.overlap = a;
    return WaltonBraun::force<2>(p, h, c).normal;
  };
  // loading on K1
  CHECK(at(1e-6) == Approx(k1 * 1e-6));
  CHECK(at(2e-6) == Approx(k1 * 2e-6));
  // unloading on K2 towards a0 = a_max (1 - K1/K2)
  const double a0 = 2e-6 * (1 - k1 / k2);
  CHECK(at(1.5e-6) == Approx(k2 * (1.5e-6 - a0)));
  // never tensile inside the permanent set
  CHECK(at(0.5 * a0) == 0.0);
  // reloading follows K2 up to a_max, then K1 again (partial latching)
  CHECK(at(1.8e-6) == Approx(k2 * (1.8e-6 - a0)));
  CHECK(at(2e-6) == Approx(k1 * 2e-6));
  CHECK(at(3e-6) == Approx(k1 * 3e-6));
}

TEST_CASE("walton_braun: monotonic slip follows the closed form of Eq. 3.3 with nu = 1",
          "[walton_braun]") {
  // At constant N and nu = 1, dT/ds = K0 (1 - T/(mu N)), so T = mu N (1 - exp(-K0 s / (mu N))).
  auto p = params(table_3_1());
  WaltonBraun::History<2> h;
  const double overlap = 1e-6, normal = p.k_load * overlap, mu_n = 0.4 * normal;
  const double k0 = 0.8 * p.k_load;
  const double dt = 1e-9, slip_speed = 1e-4;  // 1e-13 m per step
  auto c = test::state<2>(Eigen::Vector2d(1, 0), overlap, Eigen::Vector2d(0, slip_speed), dt);
  double s = 0;
  for (int k = 0; k < 20000; ++k) {
    auto f = WaltonBraun::force<2>(p, h, c);
    s += slip_speed * dt;
    REQUIRE(f.tangential.norm() <= mu_n * (1 + 1e-12));
    if (k % 2000 == 1999) {
      double expected = mu_n * (1 - std::exp(-k0 * s / mu_n));
      CHECK(f.tangential.y() == Approx(expected).epsilon(2e-3));
    }
  }
}

TEST_CASE(
    "walton_braun: a slip reversal restores the full stiffness K0 and T* holds the reversal "
    "force",
    "[walton_braun]") {
  auto p = params(table_3_1());
  WaltonBraun::History<2> h;
  const double overlap = 1e-6, mu_n = 0.4 * p.k_load * overlap, k0 = 0.8 * p.k_load;
  const double dt = 1e-9, speed = 1.0;
  auto c = test::state<2>(Eigen::Vector2d(1, 0), overlap, Eigen::Vector2d(0, speed), dt);
  double t = 0;
  for (int k = 0; k < 3000; ++k) t = WaltonBraun::force<2>(p, h, c).tangential.y();
  REQUIRE(t > 0.5 * mu_n);
  // reverse: the first increment uses K0 (Eq. 3.3 with T* = T)
  c.tangential_velocity = Eigen::Vector2d(0, -speed);
  double t_after = WaltonBraun::force<2>(p, h, c).tangential.y();
  CHECK(t - t_after == Approx(k0 * speed * dt).epsilon(1e-9));
  CHECK(h.reversal == Approx(t));  // 2D keeps T* as its component along t = (0, 1)
  // keep going: the force passes through zero towards -mu N and is limited there
  double lowest = t_after;
  for (int k = 0; k < 20000; ++k)
    lowest = std::min(lowest, WaltonBraun::force<2>(p, h, c).tangential.y());
  CHECK(lowest >= -mu_n * (1 + 1e-12));
  CHECK(lowest == Approx(-mu_n).epsilon(1e-3));
}

TEST_CASE("walton_braun: T* scales with the normal force (Eq. 3.13) and |T| <= mu N (Eq. 3.17)",
          "[walton_braun]") {
  auto p = params(table_3_1());
  WaltonBraun::History<3> h;
  auto c = test::state<3>(Eigen::Vector3d(0, 0, 1), 1e-6, Eigen::Vector3d(1e-3, 0, 0), 1e-9);
  for (int k = 0; k < 2000; ++k) WaltonBraun::force<3>(p, h, c);
  c.tangential_velocity = Eigen::Vector3d(-1e-3, 0, 0);
  WaltonBraun::force<3>(p, h, c);  // reversal: T* = T
  const double star_before = h.reversal.norm();
  const double n_before = h.previous_normal;
  c.overlap = 0.5e-6;  // unloading: N drops
  c.tangential_velocity.setZero();
  auto f = WaltonBraun::force<3>(p, h, c);
  CHECK(h.reversal.norm() == Approx(star_before * f.normal / n_before));
  CHECK(f.tangential.norm() <= 0.4 * f.normal * (1 + 1e-12));
}

TEST_CASE("walton_braun: zero friction and zero normal force give no tangential force",
          "[walton_braun]") {
  auto p = params(table_3_1(0.0));
  WaltonBraun::History<2> h;
  auto c = test::state<2>(Eigen::Vector2d(1, 0), 1e-6, Eigen::Vector2d(0, 1), 1e-8);
  auto f = WaltonBraun::force<2>(p, h, c);
  CHECK(f.tangential.norm() == 0.0);
  CHECK(std::isfinite(f.normal));
}

TEMPLATE_TEST_CASE_SIG("walton_braun: |T| <= mu N at every step of oblique impacts",
                       "[walton_braun]", ((int D), D), 2, 3) {
  for (double angle : {10.0, 30.0, 60.0, 80.0}) {
    for (double spin : {0.0, 500.0}) {
      ImpactSetup s;
      s.params = table_3_1();
      s.angle_deg = angle;
      s.spin = spin;
      std::int64_t checked = 0;
      s.each_step = [&](SimulationBase& sim) {
        for (const auto& c : sim.contacts()) {
          double t = std::sqrt(c.tangential_force[0] * c.tangential_force[0] +
                               c.tangential_force[1] * c.tangential_force[1] +
                               c.tangential_force[2] * c.tangential_force[2]);
          REQUIRE(t <= 0.4 * c.normal_force * (1 + 1e-12) + 1e-300);
          ++checked;
        }
      };
      auto res = run_impact<D>(s);
      CHECK(checked > 20);
      CHECK(std::isfinite(res.restitution));
    }
  }
}

TEST_CASE("walton_braun: T and T* survive neighbour-list rebuilds and particle re-sorting",
          "[walton_braun][history]") {
  // A skin so small that lists are rebuilt every step, and a re-sort in the
  // middle of the contact, must give the bit-identical trajectory of a run
  // with one list for the whole impact.
  for (bool wall : {false, true}) {
    INFO("particle-" << (wall ? "wall" : "particle") << " contact");
    ImpactSetup reference;
    reference.params = table_3_1();
    reference.angle_deg = 40;
    reference.wall = wall;
    reference.skin = 0.3e-3;  // larger than any motion here: no rebuild
    auto a = run_impact<2>(reference);
    ImpactSetup churn = reference;
    churn.skin = 1e-12;
    churn.sort_at_step = 30;
    auto b = run_impact<2>(churn);
    CHECK(a.rebound_tangential == b.rebound_tangential);
    CHECK(a.restitution == b.restitution);
    CHECK(a.spin_a == b.spin_a);
    // And forgetting the history would change the result (the test can fail).
    CHECK(a.spin_a != 0.0);
  }
}

TEST_CASE("walton_braun: Eq. 4.1 gives dt = 6.7e-8 s for Table 4.1", "[walton_braun][time_step]") {
  Simulation<2> sim;
  sim.add_material({"pmma", 1200, 0, 0, 0});
  sim.set_contact("pmma", "pmma", "walton_braun", table_3_1());
  ParticleSpec a;
  a.radius = 0.2e-3;
  a.material = 0;
  sim.add_particle(a);
  a.position = {1e-3, 0, 0};
  sim.add_particle(a);
  sim.prepare();
  CHECK(sim.time_step() == Approx(6.7e-8).epsilon(0.005));
  // And directly from the closed form with m = particle mass, K_N = 20000, e = 0.85, n = 40.
  const double m = sphere_mass(0.2e-3, 1200);
  CHECK(sim.time_step() == Approx(pi * 0.85 * std::sqrt(m / (2 * 20000)) / 40).epsilon(1e-12));
}

TEST_CASE(
    "walton_braun: the 2D form (T, T*, u along t) gives the 3D vector form's forces for an "
    "in-plane contact that turns, loads, unloads and reverses",
    "[walton_braun]") {
  // The 2D history keeps components along t = (-n_y, n_x); the 3D one keeps
  // vectors rotated onto the tangent plane (Eqs. 3.7-3.8). For a contact in the
  // z = 0 plane both must give the same tangential force to round-off.
  auto p = params(table_3_1(0.3));
  const auto [worst, largest] = test::in_plane_2d_3d_difference<WaltonBraun>(p, 0.5, 2e-9, false);
  REQUIRE(largest > 0);
  CHECK(worst <= 1e-9 * largest);
}

TEMPLATE_TEST_CASE_SIG(
    "walton_braun: a contact held at its largest overlap stays on the loading line's K0 "
    "(Eq. 3.4) through the round-off of its overlap",
    "[walton_braun]", ((int D), D), 2, 3) {
  // An overlap recomputed from moving centres scatters by ~1e-16 of their
  // distance: held at a_max it falls a few ulps below it on some steps. Eq. 3.4's
  // K0 must not jump to tau K2 = tau K1 / e^2 there, or a pair's tangential
  // stiffness and dissipation would be set by round-off. A real unloading (here
  // 1e-6 of the overlap) does take tau K2.
  auto p = params(table_3_1());
  const double overlap = 1e-6, dt = 1e-9, speed = 1e-4;  // 1e-13 m of slip per step
  const double k1 = p.k_load, k2 = p.k_unload, tau = p.tangential_ratio;
  for (const double below : {0.0, 2e-16, 1e-14, 1e-12, 1e-6}) {
    WaltonBraun::History<D> h;
    Vec<D> normal = Vec<D>::Zero(), along = Vec<D>::Zero();
    normal[0] = 1, along[1] = 1;
    auto c = test::state<D>(normal, overlap, Vec<D>::Zero(), dt);
    WaltonBraun::force<D>(p, h, c);  // loaded to a_max = overlap, no slip
    c.overlap = overlap * (1 - below);
    c.tangential_velocity = speed * along;
    const double t = WaltonBraun::force<D>(p, h, c).tangential.dot(along);
    INFO("overlap below a_max by " << below);
    // The first increment from T = 0 is K0 times the slip (Eq. 3.3, fraction 1).
    CHECK(t == Approx(tau * (below < 1e-9 ? k1 : k2) * speed * dt).epsilon(1e-12));
  }
}

TEMPLATE_TEST_CASE_SIG(
    "walton_braun: friction lowered during a sliding contact follows mu N as N grows again",
    "[walton_braun]", ((int D), D), 2, 3) {
  // T* set under mu = 0.4 lies beyond the lower limit 0.05 N: the contact
  // slides, and its tangential force must follow mu N up as well as down.
  using V = Eigen::Matrix<double, D, 1>;
  const auto high = params(table_3_1(0.4)), low = params(table_3_1(0.05));
  WaltonBraun::History<D> h;
  V normal = V::Zero(), along = V::Zero();
  normal[0] = 1, along[1] = 1;
  const double overlap = 1e-6, dt = 1e-9, speed = 1.0;
  auto c = test::state<D>(normal, overlap, V(speed * along), dt);
  for (int k = 0; k < 3000; ++k) WaltonBraun::force<D>(high, h, c);
  c.tangential_velocity = -speed * along;  // one step back: T* = T
  WaltonBraun::force<D>(high, h, c);
  c.tangential_velocity = speed * along;  // and on again: T* = T, near 0.4 N along the slip
  WaltonBraun::force<D>(high, h, c);
  double t = 0, n = 0;
  for (int k = 0; k < 2000; ++k) {  // the friction drops, then N rises by half
    c.overlap = overlap * (1 + 0.5 * std::min(1.0, k / 1000.0));
    const auto f = WaltonBraun::force<D>(low, h, c);
    t = f.tangential.norm(), n = f.normal;
  }
  CHECK(n == Approx(1.5 * high.k_load * overlap).epsilon(1e-12));
  // Approached as Eq. 3.3 does from T* = 0: to exp(-K0 s / (mu N)) of the gap.
  CHECK(t <= 0.05 * n * (1 + 1e-12));
  CHECK(t == Approx(0.05 * n).epsilon(1e-4));
}
