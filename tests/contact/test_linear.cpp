// Linear spring-dashpot: closed-form restitution e = exp(-pi zeta / sqrt(1 - zeta^2))
// and contact duration pi / (omega0 sqrt(1 - zeta^2)).
#include <catch2/catch.hpp>

#include "contact/linear_spring_dashpot.hpp"
#include "impact_helpers.hpp"

using namespace granule;
using granule::test::ImpactSetup;
using granule::test::run_impact;

TEMPLATE_TEST_CASE_SIG("linear: restitution and duration match the damped-oscillator closed form",
                       "[linear]", ((int D), D), 2, 3) {
  const double k = 20000, r = 0.2e-3, rho = 1200, m = sphere_mass(r, rho);
  for (double e : {0.3, 0.7, 0.9, 1.0}) {
    for (bool wall : {false, true}) {
      ImpactSetup s;
      s.model = "linear";
      s.params = {{"k_normal", k}, {"restitution", e}, {"friction", 0.3}};
      s.wall = wall;
      s.velocity = 0.7;
      s.steps_per_contact = 500;
      auto res = run_impact<D>(s);
      const double m_eff = wall ? m : m / 2;
      const double zeta = LinearSpringDashpot::damping_ratio_for(e);
      INFO("e=" << e << " wall=" << wall);
      CHECK(std::exp(-pi * zeta / std::sqrt(1 - zeta * zeta)) == Approx(e));
      CHECK(res.restitution == Approx(e).epsilon(0.005));
      const double duration = pi / (std::sqrt(k / m_eff) * std::sqrt(1 - zeta * zeta));
      CHECK(res.geometric_duration == Approx(duration).epsilon(0.005));
    }
  }
}

TEST_CASE("linear: tangential force is capped at mu |N| and the spring shortened", "[linear]") {
  const Material material{"m", 1000, 0, 0, 0};
  auto p = LinearSpringDashpot::make({{"k_normal", 1e4},
                                      {"restitution", 0.8},
                                      {"friction", 0.2},
                                      {"tangential_ratio", 2.0 / 7},
                                      {"tangential_damping_ratio", 0.5},
                                      {"allow_tension", 1}},
                                     {material, material});
  LinearSpringDashpot::History<2> h;
  auto c = test::state<2>(Eigen::Vector2d(1, 0), 1e-6, Eigen::Vector2d(0, 0.1), 1e-7);
  ContactForce<2> f;
  for (int k = 0; k < 1000; ++k) {
    f = LinearSpringDashpot::force<2>(p, h, c);
    REQUIRE(f.tangential.norm() <= 0.2 * std::abs(f.normal) * (1 + 1e-12));
  }
  CHECK(f.tangential.norm() == Approx(0.2 * f.normal));
  // The stored spring reproduces exactly the capped force.
  const double c_t = 0.5 * 2 * p.damping_ratio * std::sqrt(1e-8 * 1e4);
  // (2D keeps the spring as its elongation along t = (-n_y, n_x) = (0, 1).)
  CHECK((p.k_tangential * Eigen::Vector2d(0, h.slip) + c_t * c.tangential_velocity - f.tangential)
            .norm() == Approx(0).margin(1e-12));
}

TEST_CASE(
    "linear: the 2D form (spring along t) gives the 3D vector form's forces for an in-plane "
    "contact that turns, slides and reverses",
    "[linear]") {
  const Material material{"m", 1000, 0, 0, 0};
  auto p = LinearSpringDashpot::make({{"k_normal", 1e4},
                                      {"restitution", 0.7},
                                      {"friction", 0.3},
                                      {"tangential_ratio", 2.0 / 7},
                                      {"tangential_damping_ratio", 0.5},
                                      {"allow_tension", 0}},
                                     {material, material});
  LinearSpringDashpot::History<2> h2;
  LinearSpringDashpot::History<3> h3;
  double worst = 0, largest = 0;
  for (int k = 0; k < 6000; ++k) {
    const double angle = 0.4 * std::sin(1e-3 * k);
    const double overlap = 1e-6 * (1.2 + std::sin(2.3e-3 * k));
    const double slip_speed = 0.05 * std::cos(3.1e-3 * k);
    const Eigen::Vector2d n2(std::cos(angle), std::sin(angle)), t2(-n2.y(), n2.x());
    const Eigen::Vector3d n3(n2.x(), n2.y(), 0), t3(t2.x(), t2.y(), 0);
    auto c2 = test::state<2>(n2, overlap, Eigen::Vector2d(slip_speed * t2), 1e-7);
    auto c3 = test::state<3>(n3, overlap, Eigen::Vector3d(slip_speed * t3), 1e-7);
    c2.normal_velocity = c3.normal_velocity = 2.3e-3 * 1e-6 * std::cos(2.3e-3 * k) / 1e-7;
    const auto f2 = LinearSpringDashpot::force<2>(p, h2, c2);
    const auto f3 = LinearSpringDashpot::force<3>(p, h3, c3);
    REQUIRE(f2.normal == f3.normal);
    worst = std::max(
        worst, (Eigen::Vector3d(f2.tangential.x(), f2.tangential.y(), 0) - f3.tangential).norm());
    largest = std::max(largest, f3.tangential.norm());
  }
  REQUIRE(largest > 0);
  CHECK(worst <= 1e-9 * largest);
}
