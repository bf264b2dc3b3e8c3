// Linear spring-dashpot: closed-form restitution e = exp(-pi zeta / sqrt(1 - zeta^2))
// and contact duration pi / (omega0 sqrt(1 - zeta^2)).
#include <catch2/catch.hpp>
#include <random>

#include "contact/contact_batch.hpp"
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

// The batched 3D kernel (force_batch, contact/contact_batch.hpp) against the
// per-contact force(), lane by lane, over random contacts that cover its
// paths: new contacts (sqrt(m*) not yet computed), springs at rest, sticking
// and sliding contacts, springs that turned far (the exact rescale instead of
// the series), tension clamped or not, no tangential law at all, and lanes of
// one batch under different laws. The two
// agree to round-off (the compiler may fuse multiply-adds differently in the
// two): 1e-12 of the lane's force or spring scale.
TEST_CASE("linear: the batched 3D kernel gives force()'s forces and springs, lane by lane",
          "[linear][batch]") {
  const Material material{"m", 1000, 0, 0, 0};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto random_unit = [&] {
    Eigen::Vector3d n(unit(rng), unit(rng), unit(rng));
    while (n.norm() < 0.1) n = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    return Eigen::Vector3d(n.normalized());
  };
  constexpr int L = batch_lanes;
  int sliding = 0, sticking = 0, turned_far = 0, fresh = 0, checked = 0, no_tangential = 0;
  for (int round = 0; round < 200; ++round) {
    // Three laws per round, the lanes taking them in turn (a batch mixes
    // material pairs); every tenth round's third law has no tangential part.
    std::vector<LinearSpringDashpot::Params> laws;
    for (int law = 0; law < 3; ++law) {
      const bool none = round % 10 == 9 && law == 2;
      laws.push_back(
          LinearSpringDashpot::make({{"k_normal", 1e4 * (1 + law)},
                                     {"restitution", 0.3 + 0.3 * (unit(rng) + 1)},
                                     {"friction", none ? 0.0 : 0.1 + 0.5 * (unit(rng) + 1)},
                                     {"tangential_ratio", none ? 0.0 : 2.0 / 7},
                                     {"tangential_damping_ratio", 0.5},
                                     {"allow_tension", (round + law) % 3 != 0 ? 1.0 : 0.0}},
                                    {material, material}));
    }
    const LinearSpringDashpot::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[(l + round) % 3];
    LinearSpringDashpot::BatchHistory3 hb;
    ContactBatch<3> cb;
    cb.dt = 1e-6;
    ContactState<3> states[L];
    LinearSpringDashpot::History<3> histories[L];
    for (int l = 0; l < L; ++l) {
      ContactState<3>& c = states[l];
      c.dt = cb.dt;
      c.normal = random_unit();
      c.overlap = 1e-6 * (unit(rng) + 1.01);
      c.normal_velocity = 0.05 * unit(rng);
      const double speed = l % 2 ? 0.1 : 1e-4;  // slow lanes mostly stick
      Eigen::Vector3d v(speed * unit(rng), speed * unit(rng), speed * unit(rng));
      c.tangential_velocity = v - c.normal * c.normal.dot(v);
      c.inv_mass_sum = 1e5 * (unit(rng) + 1.5);
      LinearSpringDashpot::History<3>& h = histories[l];
      const int kind = l % 4;
      if (kind == 0) {  // new contact: no spring, sqrt(m*) to compute
        h = {};
      } else {
        Eigen::Vector3d spring(unit(rng), unit(rng), unit(rng));
        spring *= 1e-7 * (unit(rng) + 1.1);
        // Mostly in the tangent plane (the series), one lane in four turned far.
        if (kind != 3) spring -= c.normal * c.normal.dot(spring) * (1 - 1e-4 * unit(rng));
        h.slip = spring;
        h.sqrt_mass = 1.0 / std::sqrt(c.inv_mass_sum);
      }
      cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y(), cb.nz[l] = c.normal.z();
      cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
      cb.vtx[l] = c.tangential_velocity.x(), cb.vty[l] = c.tangential_velocity.y();
      cb.vtz[l] = c.tangential_velocity.z();
      cb.inv_mass_sum[l] = c.inv_mass_sum;
      hb.load(l, h);
      fresh += h.sqrt_mass < 0;
      const double old_sq = h.slip.squaredNorm();
      turned_far += old_sq > 0 && std::pow(c.normal.dot(h.slip), 2) / old_sq >= 1e-4;
    }
    LinearSpringDashpot::force_batch(lane_law, hb, cb);
    for (int l = 0; l < L; ++l) {
      LinearSpringDashpot::History<3> h = histories[l];
      const LinearSpringDashpot::Params& p = *lane_law[l];
      const ContactForce<3> f = LinearSpringDashpot::force<3>(p, h, states[l]);
      LinearSpringDashpot::History<3> hb_l;
      hb.store(l, hb_l);
      const Eigen::Vector3d t_batch(cb.ftx[l], cb.fty[l], cb.ftz[l]);
      const double force_scale = std::abs(f.normal) + f.tangential.norm() + 1e-12;
      const double spring_scale = h.slip.norm() + histories[l].slip.norm() + 1e-20;
      INFO("round " << round << " lane " << l << ": N " << f.normal << " vs " << cb.normal_force[l]
                    << ", T " << f.tangential.transpose() << " vs " << t_batch.transpose());
      REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * force_scale);
      REQUIRE((t_batch - f.tangential).norm() <= 1e-12 * force_scale);
      REQUIRE((hb_l.slip - h.slip).norm() <= 1e-12 * spring_scale);
      REQUIRE(hb_l.sqrt_mass == Approx(h.sqrt_mass).epsilon(1e-14));
      if (p.friction > 0) {
        const bool slides = f.tangential.norm() >= p.friction * std::abs(f.normal) * (1 - 1e-9);
        sliding += slides, sticking += !slides;
      } else {
        no_tangential += p.k_tangential == 0;
      }
      ++checked;
    }
  }
  INFO("sliding " << sliding << ", sticking " << sticking << ", turned far " << turned_far
                  << ", new " << fresh << ", without tangential law " << no_tangential);
  CHECK(checked == 200 * L);
  CHECK(sliding > 100);
  CHECK(sticking > 100);
  CHECK(turned_far > 100);
  CHECK(fresh > 100);
  CHECK(no_tangential > 50);
}
