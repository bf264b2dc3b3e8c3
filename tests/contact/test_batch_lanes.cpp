// The batched laws (force_batch, contact_batch.hpp) against each model's
// per-contact force(), lane by lane, over random contacts that cover the
// law's paths, in 2D and 3D, with the lanes of one batch under different
// laws. The two agree to round-off (the compiler may fuse multiply-adds
// differently in the two): 1e-12 of the lane's force scale. The 3D linear
// law has its own such test (test_linear.cpp).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <type_traits>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "contact/linear_spring_dashpot.hpp"
#include "contact/walton_braun.hpp"

using namespace granule;

namespace {
constexpr int L = batch_lanes;
const Material material{"m", 1000, 0, 0, 0};

struct Random {
  std::mt19937_64 rng{11};
  std::uniform_real_distribution<double> unit{-1.0, 1.0};
  double operator()() { return unit(rng); }
  Eigen::Vector3d direction() {
    Eigen::Vector3d n(unit(rng), unit(rng), unit(rng));
    while (n.norm() < 0.1) n = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    return n.normalized();
  }
  Eigen::Vector2d direction_2d() {
    const double angle = 3.14159265358979 * unit(rng);
    return {std::cos(angle), std::sin(angle)};
  }
};

// Three Walton-Braun laws per round; some rounds' second law has Eq. 3.3's
// exponent 1.5 (the pow instantiation), some rounds' third no friction.
std::vector<WaltonBraun::Params> walton_braun_laws(int round, Random& u) {
  std::vector<WaltonBraun::Params> laws;
  for (int law = 0; law < 3; ++law)
    laws.push_back(
        WaltonBraun::make({{"k_load", 1e4 * (1 + law)},
                           {"restitution", 0.7 + 0.25 * (u() + 1) / 2},
                           {"friction", round % 4 == 3 && law == 2 ? 0.0 : 0.2 + 0.3 * (u() + 1)},
                           {"tangential_ratio", 0.8},
                           {"slip_exponent", round % 5 == 4 && law == 1 ? 1.5 : 1.0}},
                          {material, material}));
  return laws;
}

// What the lanes covered, over all rounds.
struct Coverage {
  int loading = 0, unloading = 0, free = 0, capped = 0, fresh = 0, standing = 0, checked = 0;
};

// A Walton-Braun history for lane l: new, loading, unloading (some inside the
// permanent-set gap, N = 0), or with T near mu N and a reversal value; `along`
// gives a random tangential vector of magnitude `size` (in the plane, or not).
template <typename H, typename Along>
H walton_braun_history(int l, double overlap, double k_load, double mu, Random& u, Along along) {
  H h{};
  const int kind = l % 5;
  if (kind == 0) return h;  // a fresh contact
  const double normal = k_load * overlap;
  h.max_overlap = kind == 2 ? overlap * (1.0 + 0.6 * (u() + 1)) : overlap * (0.5 + 0.4 * (u() + 1));
  h.previous_normal = normal * (1.0 + 0.2 * u());
  const double reach = mu * normal;
  h.tangential = along(reach * (kind == 3 ? 1.0 + 0.05 * u() : 0.8 * (u() + 1) / 2));
  h.reversal = along(reach * 0.5 * u());
  h.load_direction = along(1.0);
  return h;
}
}  // namespace

TEST_CASE("walton-braun: the batched 2D kernel gives force()'s forces and history, lane by lane",
          "[walton_braun][batch]") {
  Random u;
  Coverage seen;
  for (int round = 0; round < 200; ++round) {
    const auto laws = walton_braun_laws(round, u);
    const WaltonBraun::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[(l + round) % 3];
    WaltonBraun::BatchHistory2 hb;
    ContactBatch<2> cb;
    cb.dt = 1e-7;
    ContactState<2> states[L];
    WaltonBraun::History2 histories[L];
    for (int l = 0; l < L; ++l) {
      ContactState<2>& c = states[l];
      c.dt = cb.dt;
      c.normal = u.direction_2d();
      c.overlap = 1e-6 * (u() + 1.01);
      c.normal_velocity = 0.05 * u();
      const Eigen::Vector2d t_axis(-c.normal.y(), c.normal.x());
      const double speed = l % 7 == 6 ? 0.0 : l % 2 ? 0.1 : 1e-4;  // none, sliding, sticking
      c.tangential_velocity = speed * u() * t_axis;
      c.inv_mass_sum = 1e5;
      const WaltonBraun::Params& p = *lane_law[l];
      histories[l] = walton_braun_history<WaltonBraun::History2>(
          l, c.overlap, p.k_load, p.friction, u, [&](double size) { return size; });
      if (l % 5 == 4) histories[l].load_direction = u() > 0 ? 1.0 : -1.0;
      cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y();
      cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
      cb.tangential_velocity[l] = c.tangential_velocity.dot(t_axis);
      cb.inv_mass_sum[l] = c.inv_mass_sum;
      hb.load(l, histories[l]);
    }
    WaltonBraun::force_batch(lane_law, hb, cb);
    for (int l = 0; l < L; ++l) {
      WaltonBraun::History2 h = histories[l];
      const ContactForce<2> f = WaltonBraun::force<2>(*lane_law[l], h, states[l]);
      WaltonBraun::History2 got;
      hb.store(l, got);
      const Eigen::Vector2d t_axis(-states[l].normal.y(), states[l].normal.x());
      const double t = f.tangential.dot(t_axis);
      const double scale = std::abs(f.normal) + std::abs(t) + std::abs(histories[l].tangential) +
                           std::abs(histories[l].reversal) + 1e-12;
      INFO("round " << round << " lane " << l << ": N " << f.normal << " vs " << cb.normal_force[l]
                    << ", T " << t << " vs " << cb.tangential_force[l]);
      REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * scale);
      REQUIRE(std::abs(cb.tangential_force[l] - t) <= 1e-12 * scale);
      REQUIRE(std::abs(got.tangential - h.tangential) <= 1e-12 * scale);
      REQUIRE(std::abs(got.reversal - h.reversal) <= 1e-12 * scale);
      REQUIRE(got.load_direction == h.load_direction);
      REQUIRE(got.previous_normal == Approx(h.previous_normal).epsilon(1e-14));
      REQUIRE(got.max_overlap == h.max_overlap);
      seen.loading += histories[l].max_overlap <= states[l].overlap;
      seen.unloading += histories[l].max_overlap > states[l].overlap && f.normal > 0;
      seen.free += f.normal == 0 || lane_law[l]->friction == 0;
      seen.capped += f.normal > 0 && std::abs(t) >= lane_law[l]->friction * f.normal * (1 - 1e-12);
      seen.fresh += histories[l].previous_normal == 0;
      seen.standing += states[l].tangential_velocity.squaredNorm() == 0;
      ++seen.checked;
    }
  }
  INFO("loading " << seen.loading << ", unloading " << seen.unloading << ", free " << seen.free
                  << ", capped " << seen.capped << ", fresh " << seen.fresh << ", standing "
                  << seen.standing);
  CHECK(seen.checked == 200 * L);
  CHECK(seen.loading > 200);
  CHECK(seen.unloading > 200);
  CHECK(seen.free > 50);
  CHECK(seen.capped > 100);
  CHECK(seen.fresh > 200);
  CHECK(seen.standing > 200);
}

TEST_CASE("walton-braun: the batched 3D kernel gives force()'s forces and history, lane by lane",
          "[walton_braun][batch]") {
  Random u;
  Coverage seen;
  int turned_far = 0;
  for (int round = 0; round < 200; ++round) {
    const auto laws = walton_braun_laws(round, u);
    const WaltonBraun::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[(l + round) % 3];
    WaltonBraun::BatchHistory3 hb;
    ContactBatch<3> cb;
    cb.dt = 1e-7;
    ContactState<3> states[L];
    WaltonBraun::History3 histories[L];
    for (int l = 0; l < L; ++l) {
      ContactState<3>& c = states[l];
      c.dt = cb.dt;
      c.normal = u.direction();
      c.overlap = 1e-6 * (u() + 1.01);
      c.normal_velocity = 0.05 * u();
      const double speed = l % 7 == 6 ? 0.0 : l % 2 ? 0.1 : 1e-4;
      const Eigen::Vector3d v = speed * u.direction();
      c.tangential_velocity = v - c.normal * c.normal.dot(v);
      c.inv_mass_sum = 1e5;
      const WaltonBraun::Params& p = *lane_law[l];
      // Vectors mostly in the tangent plane (the series), one lane in eight turned far.
      const bool far = l % 8 == 7;
      auto along = [&](double size) {
        Eigen::Vector3d a = u.direction();
        if (!far) a -= c.normal * c.normal.dot(a) * (1 - 1e-4 * u());
        return Eigen::Vector3d(size * a.normalized());
      };
      histories[l] =
          walton_braun_history<WaltonBraun::History3>(l, c.overlap, p.k_load, p.friction, u, along);
      turned_far += far && histories[l].tangential.squaredNorm() > 0;
      cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y(), cb.nz[l] = c.normal.z();
      cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
      cb.vtx[l] = c.tangential_velocity.x(), cb.vty[l] = c.tangential_velocity.y();
      cb.vtz[l] = c.tangential_velocity.z();
      cb.inv_mass_sum[l] = c.inv_mass_sum;
      hb.load(l, histories[l]);
    }
    WaltonBraun::force_batch(lane_law, hb, cb);
    for (int l = 0; l < L; ++l) {
      WaltonBraun::History3 h = histories[l];
      const ContactForce<3> f = WaltonBraun::force<3>(*lane_law[l], h, states[l]);
      WaltonBraun::History3 got;
      hb.store(l, got);
      const Eigen::Vector3d t(cb.ftx[l], cb.fty[l], cb.ftz[l]);
      const double scale = std::abs(f.normal) + f.tangential.norm() +
                           histories[l].tangential.norm() + histories[l].reversal.norm() + 1e-12;
      INFO("round " << round << " lane " << l << ": N " << f.normal << " vs " << cb.normal_force[l]
                    << ", T " << f.tangential.transpose() << " vs " << t.transpose());
      REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * scale);
      REQUIRE((t - f.tangential).norm() <= 1e-12 * scale);
      REQUIRE((got.tangential - h.tangential).norm() <= 1e-12 * scale);
      REQUIRE((got.reversal - h.reversal).norm() <= 1e-12 * scale);
      REQUIRE((got.load_direction - h.load_direction).norm() <= 1e-12);
      REQUIRE(got.previous_normal == Approx(h.previous_normal).epsilon(1e-14));
      REQUIRE(got.max_overlap == h.max_overlap);
      seen.loading += histories[l].max_overlap <= states[l].overlap;
      seen.unloading += histories[l].max_overlap > states[l].overlap && f.normal > 0;
      seen.free += f.normal == 0 || lane_law[l]->friction == 0;
      seen.capped +=
          f.normal > 0 && f.tangential.norm() >= lane_law[l]->friction * f.normal * (1 - 1e-12);
      seen.fresh += histories[l].previous_normal == 0;
      seen.standing += states[l].tangential_velocity.squaredNorm() == 0;
      ++seen.checked;
    }
  }
  INFO("loading " << seen.loading << ", unloading " << seen.unloading << ", free " << seen.free
                  << ", capped " << seen.capped << ", fresh " << seen.fresh << ", standing "
                  << seen.standing << ", turned far " << turned_far);
  CHECK(seen.checked == 200 * L);
  CHECK(seen.loading > 200);
  CHECK(seen.unloading > 200);
  CHECK(seen.free > 50);
  CHECK(seen.capped > 100);
  CHECK(seen.fresh > 200);
  CHECK(seen.standing > 200);
  CHECK(turned_far > 200);
}

TEST_CASE("linear: the batched 2D kernel gives force()'s forces and springs, lane by lane",
          "[linear][batch]") {
  Random u;
  int sliding = 0, sticking = 0, fresh = 0, no_tangential = 0, checked = 0;
  for (int round = 0; round < 200; ++round) {
    std::vector<LinearSpringDashpot::Params> laws;
    for (int law = 0; law < 3; ++law) {
      const bool none = round % 10 == 9 && law == 2;
      laws.push_back(
          LinearSpringDashpot::make({{"k_normal", 1e4 * (1 + law)},
                                     {"restitution", 0.3 + 0.3 * (u() + 1)},
                                     {"friction", none ? 0.0 : 0.1 + 0.5 * (u() + 1)},
                                     {"tangential_ratio", none ? 0.0 : 2.0 / 7},
                                     {"tangential_damping_ratio", 0.5},
                                     {"allow_tension", (round + law) % 3 != 0 ? 1.0 : 0.0}},
                                    {material, material}));
    }
    const LinearSpringDashpot::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[(l + round) % 3];
    LinearSpringDashpot::BatchHistory2 hb;
    ContactBatch<2> cb;
    cb.dt = 1e-6;
    ContactState<2> states[L];
    LinearSpringDashpot::History2 histories[L];
    for (int l = 0; l < L; ++l) {
      ContactState<2>& c = states[l];
      c.dt = cb.dt;
      c.normal = u.direction_2d();
      c.overlap = 1e-6 * (u() + 1.01);
      c.normal_velocity = 0.05 * u();
      const Eigen::Vector2d t_axis(-c.normal.y(), c.normal.x());
      c.tangential_velocity = (l % 2 ? 0.1 : 1e-4) * u() * t_axis;
      c.inv_mass_sum = 1e5 * (u() + 1.5);
      LinearSpringDashpot::History2& h = histories[l];
      if (l % 4 != 0) {
        h.slip = 1e-7 * u();
        h.sqrt_mass = 1.0 / std::sqrt(c.inv_mass_sum);
      }
      fresh += h.sqrt_mass < 0;
      cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y();
      cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
      cb.tangential_velocity[l] = c.tangential_velocity.dot(t_axis);
      cb.inv_mass_sum[l] = c.inv_mass_sum;
      hb.load(l, h);
    }
    LinearSpringDashpot::force_batch(lane_law, hb, cb);
    for (int l = 0; l < L; ++l) {
      LinearSpringDashpot::History2 h = histories[l];
      const LinearSpringDashpot::Params& p = *lane_law[l];
      const ContactForce<2> f = LinearSpringDashpot::force<2>(p, h, states[l]);
      LinearSpringDashpot::History2 got;
      hb.store(l, got);
      const Eigen::Vector2d t_axis(-states[l].normal.y(), states[l].normal.x());
      const double t = f.tangential.dot(t_axis);
      const double force_scale = std::abs(f.normal) + std::abs(t) + 1e-12;
      const double spring_scale = std::abs(h.slip) + std::abs(histories[l].slip) + 1e-20;
      INFO("round " << round << " lane " << l << ": N " << f.normal << " vs " << cb.normal_force[l]
                    << ", T " << t << " vs " << cb.tangential_force[l]);
      REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * force_scale);
      REQUIRE(std::abs(cb.tangential_force[l] - t) <= 1e-12 * force_scale);
      REQUIRE(std::abs(got.slip - h.slip) <= 1e-12 * spring_scale);
      REQUIRE(got.sqrt_mass == Approx(h.sqrt_mass).epsilon(1e-14));
      if (p.friction > 0) {
        const bool slides = std::abs(t) >= p.friction * std::abs(f.normal) * (1 - 1e-9);
        sliding += slides, sticking += !slides;
      } else {
        no_tangential += p.k_tangential == 0;
      }
      ++checked;
    }
  }
  INFO("sliding " << sliding << ", sticking " << sticking << ", new " << fresh
                  << ", without tangential law " << no_tangential);
  CHECK(checked == 200 * L);
  CHECK(sliding > 100);
  CHECK(sticking > 100);
  CHECK(fresh > 100);
  CHECK(no_tangential > 50);
}

// Hertz-Mindlin's lanes: new, sticking and sliding contacts, slips that
// turned far (3D), with three material pairs' laws in one batch.
template <int D>
void check_hertz_mindlin_lanes() {
  Random u;
  int sliding = 0, sticking = 0, turned_far = 0, checked = 0;
  const Material soft{"soft", 1000, 1e7, 0.3, 0}, hard{"hard", 2500, 2e8, 0.25, 0};
  for (int round = 0; round < 200; ++round) {
    std::vector<HertzMindlin::Params> laws;
    const Material* pairs[3][2] = {{&soft, &soft}, {&soft, &hard}, {&hard, &hard}};
    for (int law = 0; law < 3; ++law)
      laws.push_back(HertzMindlin::make({{"restitution", 0.3 + 0.3 * (u() + 1)},
                                         {"friction", 0.1 + 0.4 * (u() + 1)},
                                         {"calibrate_restitution", law == 1 ? 0.0 : 1.0}},
                                        {*pairs[law][0], *pairs[law][1]}));
    const HertzMindlin::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[(l + round) % 3];
    typename HertzMindlin::template History<D> histories[L];
    ContactState<D> states[L];
    ContactBatch<D> cb;
    cb.dt = 1e-7;
    std::conditional_t<D == 2, HertzMindlin::BatchHistory2, HertzMindlin::BatchHistory3> hb;
    for (int l = 0; l < L; ++l) {
      ContactState<D>& c = states[l];
      c.dt = cb.dt;
      c.overlap = 1e-6 * (u() + 1.01);
      c.normal_velocity = 0.05 * u();
      c.inv_mass_sum = 1e5 * (u() + 1.5);
      c.effective_mass = 1.0 / c.inv_mass_sum;
      c.effective_radius = 1e-4 * (u() + 1.5);
      const double speed = l % 2 ? 0.1 : 1e-4;
      if constexpr (D == 2) {
        c.normal = u.direction_2d();
        const Eigen::Vector2d t_axis(-c.normal.y(), c.normal.x());
        c.tangential_velocity = speed * u() * t_axis;
        if (l % 4 != 0) histories[l].slip = 1e-8 * u() * t_axis;
        if (l % 4 == 3) histories[l].slip = 1e-8 * Eigen::Vector2d(u(), u());  // off the line
        cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y();
        cb.tangential_velocity[l] = c.tangential_velocity.dot(t_axis);
      } else {
        c.normal = u.direction();
        const Eigen::Vector3d v = speed * u.direction();
        c.tangential_velocity = v - c.normal * c.normal.dot(v);
        Eigen::Vector3d spring = 1e-8 * u.direction();
        if (l % 4 != 3) spring -= c.normal * c.normal.dot(spring) * (1 - 1e-4 * u());
        if (l % 4 != 0) histories[l].slip = spring;
        turned_far += l % 4 == 3;
        cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y(), cb.nz[l] = c.normal.z();
        cb.vtx[l] = c.tangential_velocity.x(), cb.vty[l] = c.tangential_velocity.y();
        cb.vtz[l] = c.tangential_velocity.z();
      }
      cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
      cb.inv_mass_sum[l] = c.inv_mass_sum;
      cb.effective_radius[l] = c.effective_radius;
      hb.load(l, histories[l]);
    }
    HertzMindlin::force_batch(lane_law, hb, cb);
    for (int l = 0; l < L; ++l) {
      auto h = histories[l];
      const ContactForce<D> f = HertzMindlin::force<D>(*lane_law[l], h, states[l]);
      typename HertzMindlin::template History<D> got;
      hb.store(l, got);
      Vec<D> t;
      if constexpr (D == 2)
        t = cb.tangential_force[l] * Eigen::Vector2d(-cb.ny[l], cb.nx[l]);
      else
        t = Eigen::Vector3d(cb.ftx[l], cb.fty[l], cb.ftz[l]);
      const double force_scale = std::abs(f.normal) + f.tangential.norm() + 1e-12;
      const double spring_scale = h.slip.norm() + histories[l].slip.norm() + 1e-20;
      INFO(D << "D, round " << round << " lane " << l << ": N " << f.normal << " vs "
             << cb.normal_force[l] << ", T " << f.tangential.transpose() << " vs "
             << t.transpose());
      REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * force_scale);
      REQUIRE((t - f.tangential).norm() <= 1e-12 * force_scale);
      REQUIRE((got.slip - h.slip).norm() <= 1e-12 * spring_scale);
      const bool slides = f.tangential.norm() >= lane_law[l]->friction * f.normal * (1 - 1e-9);
      sliding += slides, sticking += !slides;
      ++checked;
    }
  }
  INFO("sliding " << sliding << ", sticking " << sticking << ", turned far " << turned_far);
  CHECK(checked == 200 * L);
  CHECK(sliding > 100);
  CHECK(sticking > 100);
  if (D == 3) CHECK(turned_far > 100);
}

TEST_CASE("hertz-mindlin: the batched kernels give force()'s forces and slips, lane by lane",
          "[hertz_mindlin][batch]") {
  check_hertz_mindlin_lanes<2>();
  check_hertz_mindlin_lanes<3>();
}
