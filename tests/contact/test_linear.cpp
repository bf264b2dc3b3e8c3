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
  const auto [worst, largest] =
      test::in_plane_2d_3d_difference<LinearSpringDashpot>(p, 0.05, 1e-7, true);
  REQUIRE(largest > 0);
  CHECK(worst <= 1e-9 * largest);
}
