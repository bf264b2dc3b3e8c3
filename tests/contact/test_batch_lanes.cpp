// The batched laws (force_batch, contact_batch.hpp) against each model's
// per-contact force(), lane by lane, over random contacts that cover the
// law's paths, in 2D and 3D, with the lanes of one batch under different
// laws. The two agree to round-off (the compiler may fuse multiply-adds
// differently in the two): 1e-12 of the lane's force scale, and for
// Thornton's elastic law what its cube root and its ties make of round-off
// (check_thornton_elastic_lanes). The 3D linear law has its own such test
// (test_linear.cpp).
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "contact/linear_spring_dashpot.hpp"
#include "contact/thornton_elastic.hpp"
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
  int forgotten = 0;  // lanes whose T* reached mu N along the slip and was cleared
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
  // Some beyond mu N: the friction lowered while the contact lasts (forgets_reversal).
  h.reversal = along(reach * (kind == 4 ? 1.5 : 0.5) * u());
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
      // The law reads no mass (batch_needs_mass is false: the engine never
      // fetches it), so a NaN here must not reach a force.
      cb.inv_mass_sum[l] = std::numeric_limits<double>::quiet_NaN();
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
      seen.forgotten += f.normal > 0 && lane_law[l]->friction > 0 &&
                        histories[l].previous_normal > 0 && histories[l].reversal != 0 &&
                        h.reversal == 0;
      ++seen.checked;
    }
  }
  INFO("loading " << seen.loading << ", unloading " << seen.unloading << ", free " << seen.free
                  << ", capped " << seen.capped << ", fresh " << seen.fresh << ", standing "
                  << seen.standing << ", forgotten " << seen.forgotten);
  CHECK(seen.checked == 200 * L);
  CHECK(seen.loading > 200);
  CHECK(seen.unloading > 200);
  CHECK(seen.free > 50);
  CHECK(seen.capped > 100);
  CHECK(seen.fresh > 200);
  CHECK(seen.standing > 200);
  CHECK(seen.forgotten > 50);
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
      // The law reads no mass (batch_needs_mass is false: the engine never
      // fetches it), so a NaN here must not reach a force.
      cb.inv_mass_sum[l] = std::numeric_limits<double>::quiet_NaN();
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
      seen.forgotten += f.normal > 0 && lane_law[l]->friction > 0 &&
                        histories[l].previous_normal > 0 &&
                        histories[l].reversal.squaredNorm() > 0 && h.reversal.squaredNorm() == 0;
      ++seen.checked;
    }
  }
  INFO("loading " << seen.loading << ", unloading " << seen.unloading << ", free " << seen.free
                  << ", capped " << seen.capped << ", fresh " << seen.fresh << ", standing "
                  << seen.standing << ", forgotten " << seen.forgotten << ", turned far "
                  << turned_far);
  CHECK(seen.checked == 200 * L);
  CHECK(seen.loading > 200);
  CHECK(seen.unloading > 200);
  CHECK(seen.free > 50);
  CHECK(seen.capped > 100);
  CHECK(seen.fresh > 200);
  CHECK(seen.standing > 200);
  CHECK(seen.forgotten > 50);
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
                                         {"calibrate_restitution", law == 1 ? 0.0 : 1.0},
                                         {"shrink_rescale", law == 2 ? 1.0 : 0.0}},
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

namespace {
// What Thornton-elastic's lanes went through, over all rounds and steps (each
// counted from force()'s histories before and after the step).
struct ThorntonCoverage {
  int fresh = 0, no_friction = 0, apart = 0, padded = 0;
  int to_unloading = 0, to_reloading = 0, unloading = 0, reloading = 0;
  int masing_return = 0, no_slip = 0, partial_slip = 0, capped = 0, reversal_capped = 0;
  int standing_on_u = 0, u_across = 0, turned_far = 0, checked = 0;
  int round_off = 0, ties = 0;  // lanes within 1e-12 of force(); force()'s own ties
};

// One lane's contact over a round: its normal turning a little each step (and
// in some lanes sometimes far), its overlap growing or shrinking (N loading or
// unloading), and its slip along a tangent direction whose sense flips at
// random (Eqs. 6.8-6.10's reversals), at one of four speeds: none, slow enough
// for dT < mu dN (theta = 1), partial slip, sliding; in 3D some lanes also slip
// across T's line.
template <int D>
struct ThorntonLane {
  Vec<D> normal, along;
  double overlap, rate, radius, speed, across;
};

template <int D>
Vec<D> random_direction(Random& u) {
  if constexpr (D == 2)
    return u.direction_2d();
  else
    return u.direction();
}

// The unit tangent nearest `guess` (in 2D: +t or -t, t = (-n_y, n_x)).
template <int D>
Vec<D> thornton_tangent(const Vec<D>& normal, const Vec<D>& guess) {
  if constexpr (D == 2) {
    const Vec<2> t(-normal.y(), normal.x());
    return guess.dot(t) < 0 ? Vec<2>(-t) : t;
  } else {
    return (guess - normal * normal.dot(guess)).normalized();
  }
}

// Thornton-elastic's lanes against force(), step after step: each step the
// batch is loaded from force()'s history of the step before, so that every
// lane is checked from the states a contact really reaches (reversal points,
// branches) without the two paths' round-off adding up over a round.
template <int D>
void check_thornton_elastic_lanes() {
  using TE = ThorntonElastic;
  using History = TE::History<D>;
  Random u;
  ThorntonCoverage seen;
  const Material soft{"soft", 1000, 1e7, 0.3, 0}, hard{"hard", 2500, 2e8, 0.25, 0};
  const Material* pairs[3][2] = {{&soft, &soft}, {&soft, &hard}, {&hard, &hard}};
  constexpr int rounds = 100, steps = 16;
  for (int round = 0; round < rounds; ++round) {
    std::vector<TE::Params> laws;
    for (int law = 0; law < 3; ++law) {
      const double mu = round % 5 == 4 && law == 2 ? 0.0 : 0.1 + 0.2 * (u() + 1);
      laws.push_back(TE::make({{"friction", mu}}, {*pairs[law][0], *pairs[law][1]}));
    }
    // Some rounds all lanes under one law (LaneParams<true>), the others mixed.
    const TE::Params* lane_law[L];
    for (int l = 0; l < L; ++l) lane_law[l] = &laws[round % 3 == 0 ? 0 : (l + round) % 3];
    // Some rounds with the last lanes padded, as the engine pads a batch it could not fill.
    const int used = round % 4 == 1 ? L - 5 : L;
    ThorntonLane<D> lanes[L];
    History histories[L];
    for (int l = 0; l < L; ++l) {
      ThorntonLane<D>& s = lanes[l];
      s.normal = random_direction<D>(u);
      s.along = thornton_tangent<D>(s.normal, random_direction<D>(u));
      s.overlap = 1e-6 * (u() + 1.2);
      s.rate = 0.04 * s.overlap * u();
      s.radius = 1e-4 * (u() + 1.5);
      const int kind = l % 4;
      s.speed = kind == 0 ? (l % 8 == 0 ? 0.0 : 1e-5) : kind == 1 ? 0.02 : kind == 2 ? 0.1 : 0.5;
      s.across = D == 3 && l % 3 == 0 ? 0.3 * u() : 0.0;
      // A quarter of the lanes start on a branch with reversal values (some
      // with T = 0 and a sense u, the line force() then reads u along).
      if (l % 4 == 3 || l % 8 == 4) {
        History& h = histories[l];
        const TE::Params& p = *lane_law[l];
        const double a = std::sqrt(s.overlap * s.radius);
        const double cap = p.friction * 4.0 / 3.0 * p.e_star * a * s.overlap;
        h.previous_normal = cap > 0 ? cap / p.friction * (1 + 0.05 * u()) : 0.0;
        h.branch = static_cast<int>(3 * (u() + 1) / 2) % 3;
        h.tangential = l % 8 == 4 ? Vec<D>(Vec<D>::Zero()) : Vec<D>(0.9 * cap * u() * s.along);
        h.reversal = 0.9 * cap * u() * s.along;
        h.reversal2 = 0.9 * cap * u() * s.along;
        h.load_direction = (u() < 0 ? -1.0 : 1.0) * s.along;
        // Some with u across the tangent plane (along the normal): rotated,
        // it vanishes; force() then takes the next increment as the first, and
        // keeps the old u where there is none.
        if (l % 16 == 11 || l % 16 == 12) h.load_direction = (u() < 0 ? -1.0 : 1.0) * s.normal;
        if (l % 8 == 4) s.speed = 0.0;
      }
    }
    for (int step = 0; step < steps; ++step) {
      std::conditional_t<D == 2, TE::BatchHistory2, TE::BatchHistory3> hb;
      ContactBatch<D> cb;
      cb.dt = 1e-7;
      ContactState<D> states[L];
      bool turned_far[L] = {};
      for (int l = 0; l < L; ++l) {
        ThorntonLane<D>& s = lanes[l];
        // The contact moves on: the normal turns (far, x > 1e-4, in some lanes
        // now and then), the overlap changes (in some lanes across zero), the
        // slip's sense flips at random.
        if (step > 0) {
          turned_far[l] = l % 8 == 7 && u() > 0.5;
          const Vec<D> kick = random_direction<D>(u);
          s.normal = (s.normal + (turned_far[l] ? 0.05 : 1e-3) * kick).normalized();
          s.along = thornton_tangent<D>(s.normal, s.along);
          if (u() > 0.6) s.rate = -s.rate;
          s.overlap += s.rate;
          if (l % 16 == 15 && u() > 0.8) s.overlap = -0.2e-6 * (u() + 1.01);
          if (s.overlap <= 0 && u() > 0.5) s.overlap = 1e-6 * (u() + 1.2);  // touching again
          if (u() > 0.5) s.speed = -s.speed;
        }
        ContactState<D>& c = states[l];
        c.dt = cb.dt;
        c.normal = s.normal;
        c.overlap = s.overlap;
        c.normal_velocity = -s.rate / cb.dt;
        c.inv_mass_sum = 1e5;
        c.effective_mass = 1e-5;
        c.effective_radius = s.radius;
        Vec<D> v = s.speed * s.along;
        if constexpr (D == 3) {
          const Vec<3> side = s.normal.cross(s.along);
          v += s.across * std::abs(s.speed) * side;
        }
        c.tangential_velocity = v;
        if (l >= used) {  // a padded lane, as PairBatch::pad() leaves it
          c.normal = Vec<D>::Unit(0);
          c.overlap = -0.5, c.normal_velocity = 0, c.effective_radius = 0.125;
          c.tangential_velocity.setZero();
          c.inv_mass_sum = 1;
        }
        cb.nx[l] = c.normal.x(), cb.ny[l] = c.normal.y();
        cb.overlap[l] = c.overlap, cb.normal_velocity[l] = c.normal_velocity;
        // The law reads no mass (batch_needs_mass is false: the engine never
        // fetches it), so a NaN here must not reach a force.
        cb.inv_mass_sum[l] = std::numeric_limits<double>::quiet_NaN();
        cb.effective_radius[l] = c.effective_radius;
        if constexpr (D == 2) {
          cb.tangential_velocity[l] =
              c.tangential_velocity.dot(Vec<2>(-c.normal.y(), c.normal.x()));
        } else {
          cb.nz[l] = c.normal.z();
          cb.vtx[l] = c.tangential_velocity.x(), cb.vty[l] = c.tangential_velocity.y();
          cb.vtz[l] = c.tangential_velocity.z();
        }
        if (l < used)
          hb.load(l, histories[l]);
        else
          hb.pad(l);
      }
      TE::force_batch(lane_law, hb, cb);
      for (int l = 0; l < L; ++l) {
        History got;
        hb.store(l, got);
        Vec<D> t;
        if constexpr (D == 2)
          t = cb.tangential_force[l] * Vec<2>(-cb.ny[l], cb.nx[l]);
        else
          t = Vec<3>(cb.ftx[l], cb.fty[l], cb.ftz[l]);
        if (l >= used) {  // padding: no force, and nothing kept
          REQUIRE(cb.normal_force[l] == 0);
          REQUIRE(t.squaredNorm() == 0);
          REQUIRE(got.tangential.squaredNorm() + got.reversal.squaredNorm() +
                      got.reversal2.squaredNorm() + got.load_direction.squaredNorm() ==
                  0);
          REQUIRE(got.previous_normal == 0);
          ++seen.padded;
          continue;
        }
        const History before = histories[l];
        History& h = histories[l];
        const TE::Params& p = *lane_law[l];
        const ContactState<D>& c = states[l];
        const ContactForce<D> f = TE::force<D>(p, h, c);
        const double scale = std::abs(f.normal) + f.tangential.norm() + before.tangential.norm() +
                             before.reversal.norm() + before.reversal2.norm() + 1e-20;
        INFO(D << "D, round " << round << " step " << step << " lane " << l << ": branch "
               << before.branch << " -> " << h.branch << " vs " << got.branch << "; N " << f.normal
               << " vs " << cb.normal_force[l] << ", T " << f.tangential.transpose() << " vs "
               << t.transpose() << ", T* " << h.reversal.transpose() << " vs "
               << got.reversal.transpose() << ", T** " << h.reversal2.transpose() << " vs "
               << got.reversal2.transpose());
        REQUIRE(std::abs(cb.normal_force[l] - f.normal) <= 1e-12 * scale);
        REQUIRE(got.previous_normal == Approx(h.previous_normal).epsilon(1e-14));
        // Round-off of the lane's forces, and what Eq. 6.7's cube root makes of
        // it where theta^3 is round-off away from 0 (a contact sliding on, T at
        // mu N of the step before: T + mu dN is mu N): a round-off e there is
        // e^(1/3) ~ 1e-5 in theta, times the step's increment k0 |d delta| + mu |dN|.
        const bool touching = c.overlap > 0;
        const double k0 = touching ? 8 * p.g_star * std::sqrt(c.overlap * c.effective_radius) : 0.0;
        const double slip_mag = c.tangential_velocity.norm() * c.dt;
        const double mu_dn = p.friction * (f.normal - before.previous_normal);
        const double tolerance = 1e-12 * scale + 1e-5 * (k0 * slip_mag + std::abs(mu_dn));
        auto agrees = [&](const History& want, const Vec<D>& want_t, double tol) {
          return got.branch == want.branch && (t - want_t).norm() <= tol &&
                 (got.tangential - want.tangential).norm() <= tol &&
                 (got.reversal - want.reversal).norm() <= tol &&
                 (got.reversal2 - want.reversal2).norm() <= tol &&
                 (got.load_direction - want.load_direction).norm() <= 1e-12;
        };
        bool same = agrees(h, f.tangential, tolerance);
        seen.round_off += agrees(h, f.tangential, 1e-12 * scale);
        if (!same) {
          // A tie in force() itself: its Masing returns compare T with +-T*
          // (or T**), and where both were capped at the same mu N the two are
          // equal but for round-off, which the two paths' arithmetic (fused
          // multiply-adds) may break either way. The lane must then be force()
          // on inputs a few ulp away.
          const double ulps[3] = {1 - 2e-15, 1.0, 1 + 2e-15};
          for (double ft : ulps)
            for (double fr : ulps)
              for (double fq : ulps) {
                History moved = before;
                moved.tangential *= ft, moved.reversal *= fr, moved.reversal2 *= fq;
                const ContactForce<D> fm = TE::force<D>(p, moved, c);
                same = same || agrees(moved, fm.tangential, tolerance);
              }
          seen.ties += same;
        }
        REQUIRE(same);
        ++seen.checked;
        // What this step went through (force()'s view).
        const double limit = p.friction * f.normal;
        if (!(c.overlap > 0)) {
          ++seen.apart;
          continue;
        }
        seen.fresh += before.previous_normal == 0;
        if (!(limit > 0)) {
          ++seen.no_friction;
          continue;
        }
        if (slip_mag > 0) (k0 * slip_mag < mu_dn ? seen.no_slip : seen.partial_slip)++;
        seen.to_unloading += h.branch == TE::unloading && before.branch != TE::unloading;
        seen.to_reloading += h.branch == TE::reloading && before.branch != TE::reloading;
        seen.unloading += h.branch == TE::unloading;
        seen.reloading += h.branch == TE::reloading;
        // Masing: a reversed branch that got back to the curve it left. Counted
        // where the step began off loading and moved, and ended on loading.
        seen.masing_return += before.branch != TE::loading && h.branch == TE::loading &&
                              before.load_direction.squaredNorm() > 0;
        seen.capped += f.tangential.norm() >= limit * (1 - 1e-12);
        seen.reversal_capped +=
            h.reversal.norm() >= limit * (1 - 1e-12) || h.reversal2.norm() >= limit * (1 - 1e-12);
        seen.standing_on_u += before.tangential.squaredNorm() == 0 && slip_mag == 0 &&
                              before.load_direction.squaredNorm() > 0;
        seen.turned_far += turned_far[l] && before.tangential.squaredNorm() > 0;
        seen.u_across += std::abs(before.load_direction.dot(c.normal)) > 0.999;
      }
    }
  }
  INFO(D << "D: checked " << seen.checked << ", fresh " << seen.fresh << ", no friction "
         << seen.no_friction << ", apart " << seen.apart << ", padded " << seen.padded
         << ", to unloading " << seen.to_unloading << ", to reloading " << seen.to_reloading
         << ", unloading " << seen.unloading << ", reloading " << seen.reloading
         << ", Masing returns " << seen.masing_return << ", no slip " << seen.no_slip
         << ", partial slip " << seen.partial_slip << ", capped " << seen.capped
         << ", reversal capped " << seen.reversal_capped << ", standing on u " << seen.standing_on_u
         << ", u across " << seen.u_across << ", turned far " << seen.turned_far
         << "; to round-off " << seen.round_off << ", ties " << seen.ties);
  CHECK(seen.checked > 10000);
  // Nearly all lanes within round-off; ties and amplified round-off are rare.
  CHECK(seen.round_off > 0.99 * seen.checked);
  CHECK(seen.ties < 0.001 * seen.checked);
  CHECK(seen.fresh > 100);
  CHECK(seen.no_friction > 100);
  CHECK(seen.apart > 10);
  CHECK(seen.padded > 1000);
  CHECK(seen.to_unloading > 100);
  CHECK(seen.to_reloading > 100);
  CHECK(seen.unloading > 500);
  CHECK(seen.reloading > 500);
  CHECK(seen.masing_return > 50);
  CHECK(seen.no_slip > 100);
  CHECK(seen.partial_slip > 1000);
  CHECK(seen.capped > 100);
  CHECK(seen.reversal_capped > 100);
  CHECK(seen.standing_on_u > 10);
  CHECK(seen.u_across > 50);
  if (D == 3) CHECK(seen.turned_far > 100);
}
}  // namespace

TEST_CASE(
    "thornton-elastic: the batched 2D kernel gives force()'s forces and history, lane by lane",
    "[thornton][batch]") {
  check_thornton_elastic_lanes<2>();
}

TEST_CASE(
    "thornton-elastic: the batched 3D kernel gives force()'s forces and history, lane by lane",
    "[thornton][batch]") {
  check_thornton_elastic_lanes<3>();
}
