// Thornton's elastic (Hertz + Mindlin-Deresiewicz) and auto-adhesive (JKR +
// Savkoor-Briggs + Mindlin-Deresiewicz) contacts, dissertation 6.3-6.4: the
// kernels are driven step by step here, with the two-body equations of motion
// integrated in the test, and compared with closed forms.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "contact/thornton_elastic.hpp"
#include "contact/thornton_jkr.hpp"
#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {

// Dissertation 6.4: R = 100 um, rho = 2.65 Mg/m^3, E = 70 GPa, nu = 0.3, mu = 0.35;
// gamma = 0.2 J/m^2 for the adhesive runs.
const double radius = 100e-6, density = 2650, young = 70e9, poisson = 0.3, mu = 0.35;
const Material glass{"glass", density, young, poisson, 0.2};

ThorntonElastic::Params elastic_params(double friction) {
  return ThorntonElastic::make({{"friction", friction}}, {glass, glass});
}
ThorntonJkr::Params jkr_params(double friction, double gamma) {
  return ThorntonJkr::make({{"friction", friction}, {"surface_energy", gamma}}, {glass, glass});
}

// As granule::test::state (impact_helpers.hpp), without pulling in the engine.
template <int D>
ContactState<D> state(const Vec<D>& normal, double overlap, const Vec<D>& tangential_velocity,
                      double dt, double effective_mass = 1e-8, double effective_radius = 1e-4) {
  ContactState<D> c;
  c.normal = normal;
  c.overlap = overlap;
  c.normal_velocity = 0;
  c.tangential_velocity = tangential_velocity;
  c.effective_mass = effective_mass;
  c.inv_mass_sum = 1.0 / effective_mass;
  c.effective_radius = effective_radius;
  c.dt = dt;
  return c;
}

template <int D>
Vec<D> planar(double x, double y) {
  Vec<D> v = Vec<D>::Zero();
  v[0] = x;
  v[1] = y;
  return v;
}
// Spin about z (the motion stays in the x-y plane in both dimensions).
template <int D>
Vec<D> spin_cross(double w, const Vec<D>& r) {
  return planar<D>(-w * r[1], w * r[0]);
}
template <int D>
double torque_z(const Vec<D>& r, const Vec<D>& f) {
  return r[0] * f[1] - r[1] * f[0];
}

template <int D>
bool finite_history(const ThorntonElastic::History<D>& h) {
  return h.tangential.allFinite() && h.reversal.allFinite() && h.reversal2.allFinite() &&
         h.load_direction.allFinite() && std::isfinite(h.previous_normal);
}
template <int D>
bool finite_history(const ThorntonJkr::History<D>& h) {
  return finite_history(h.md) && std::isfinite(h.contact_radius) &&
         std::isfinite(h.separation_overlap);
}

// A head-on impact, integrated in the overlap alone with velocity Verlet:
// m* d^2(alpha)/dt^2 = -N(alpha). The contact starts at alpha = 0.
struct NormalImpact {
  double duration = 0;     // s, first to last step in contact (end interpolated for Hertz)
  double max_overlap = 0;  // m
  double restitution = 0;  // -v_out / v_in, once separated
  double min_normal = 0, max_normal = 0;
  bool separated = false;
  bool finite = true;
};

template <typename M, int D>
NormalImpact normal_impact(const typename M::Params& p, double m_eff, double r_eff, double v_in,
                           double dt, long max_steps) {
  typename M::template History<D> h;
  auto c = state<D>(Vec<D>::UnitX(), 0.0, Vec<D>::Zero(), dt, m_eff, r_eff);
  NormalImpact out;
  double alpha = 0, v = v_in, normal = 0, t = 0;
  bool started = false;
  for (long k = 0; k < max_steps; ++k) {
    const double half = v - 0.5 * normal / m_eff * dt;
    const double previous = alpha;
    alpha += half * dt;
    t += dt;
    c.overlap = alpha;
    c.normal_velocity = half;
    bool in = M::touching(p, h, alpha);
    if (in) {
      auto f = M::template force<D>(p, h, c);
      normal = f.normal;
      out.finite = out.finite && std::isfinite(f.normal) && f.tangential.allFinite();
    } else {
      h = {};
      normal = 0;
    }
    v = half - 0.5 * normal / m_eff * dt;
    if (in) {
      started = true;
      out.max_overlap = std::max(out.max_overlap, alpha);
      out.min_normal = std::min(out.min_normal, normal);
      out.max_normal = std::max(out.max_normal, normal);
    } else if (started) {
      // For Hertz the force vanishes at alpha = 0: interpolate the crossing.
      out.duration = previous > 0 && alpha <= 0 ? t - dt + dt * previous / (previous - alpha) : t;
      out.separated = true;
      out.restitution = -v / v_in;
      return out;
    }
  }
  out.duration = t;
  return out;
}

// Two identical spheres in the x-y plane with spin about z, advanced with the
// engine's leap-frog (kick, then drift) and its contact conventions.
template <typename M, int D>
struct TwoSpheres {
  typename M::Params p;
  typename M::template History<D> h{};
  double r = radius, m = sphere_mass(radius, density), inertia = sphere_inertia(m, radius);
  Vec<D> x[2], v[2];
  double w[2] = {0, 0};
  double dt;
  // Last step:
  bool in_contact = false;
  ContactState<D> c;
  ContactForce<D> f;

  TwoSpheres(const typename M::Params& params, double speed, double angle_deg, double step)
      : p(params), dt(step) {
    const double th = angle_deg * pi / 180;
    x[0] = planar<D>(-r, 0);  // touching: the first drift makes the overlap positive
    x[1] = planar<D>(r, 0);
    v[0] = planar<D>(0.5 * speed * std::cos(th), 0.5 * speed * std::sin(th));
    v[1] = -v[0];
  }
  void step() {
    const Vec<D> d = x[0] - x[1];
    const double dist = d.norm(), overlap = 2 * r - dist;
    Vec<D> total = Vec<D>::Zero();
    double torque = 0;
    in_contact = M::touching(p, h, overlap);
    if (!in_contact) {
      h = {};
      f = {};
    } else {
      c.normal = d / dist;
      c.overlap = overlap;
      const Vec<D> v_rel = v[1] - v[0];
      c.normal_velocity = v_rel.dot(c.normal);
      c.tangential_velocity = v_rel - c.normal * c.normal_velocity +
                              r * spin_cross<D>(w[0], c.normal) + r * spin_cross<D>(w[1], c.normal);
      c.effective_mass = m / 2;
      c.inv_mass_sum = 2 / m;
      c.effective_radius = r / 2;
      c.dt = dt;
      f = M::template force<D>(p, h, c);
      total = f.normal * c.normal + f.tangential;
      torque = torque_z<D>(-(r - 0.5 * overlap) * c.normal, f.tangential);
    }
    v[0] += total / m * dt;
    v[1] -= total / m * dt;
    w[0] += torque / inertia * dt;
    w[1] += torque / inertia * dt;
    x[0] += v[0] * dt;
    x[1] += v[1] * dt;
  }
  // Tangential force along the in-plane tangent (normal turned by +90 degrees).
  double tangential_component() const {
    return f.tangential.dot(planar<D>(-c.normal[1], c.normal[0]));
  }
};

// Mindlin's virgin loading curve at constant N (Johnson 1985, Eq. 7.39):
// T = mu N [1 - (1 - 16 G* a delta / (3 mu N))^{3/2}].
double mindlin_virgin(double delta, double k0, double mu_n) {
  const double x = 1 - 2 * k0 * std::abs(delta) / (3 * mu_n);  // k0 = 8 G* a
  const double t = x > 0 ? mu_n * (1 - x * std::sqrt(x)) : mu_n;
  return delta < 0 ? -t : t;
}

}  // namespace

TEMPLATE_TEST_CASE_SIG(
    "thornton: Hertz normal impact lasts 2.868 (m*^2/(R* E*^2 v))^{1/5}, "
    "reaches (15 m* v^2/(16 E* sqrt R*))^{2/5} and conserves energy",
    "[thornton]", ((int D), D), 2, 3) {
  const auto p = elastic_params(0.0);
  const double e_star = young / (2 * (1 - poisson * poisson));
  REQUIRE(p.e_star == Approx(e_star).epsilon(1e-14));
  const double m = sphere_mass(radius, density);
  for (bool wall : {false, true}) {
    // A wall of the same glass: m* = m, R* = R; two spheres: m/2, R/2.
    const double m_eff = wall ? m : m / 2, r_eff = wall ? radius : radius / 2;
    for (double v : {0.01, 0.1, 1.0, 10.0}) {
      const double duration = 2.868 * std::pow(m_eff * m_eff / (r_eff * e_star * e_star * v), 0.2);
      const double max_overlap =
          std::pow(15 * m_eff * v * v / (16 * e_star * std::sqrt(r_eff)), 0.4);
      const double dt = duration / 20000;
      auto res = normal_impact<ThorntonElastic, D>(p, m_eff, r_eff, v, dt, 100000);
      INFO("D=" << D << " wall=" << wall << " v=" << v);
      REQUIRE(res.separated);
      REQUIRE(res.finite);
      // 2.868 is the integral 2 (alpha_max/v) int_0^1 dx/sqrt(1-x^{5/2}) rounded to 4 digits.
      CHECK(res.duration == Approx(duration).epsilon(2e-4));
      CHECK(res.max_overlap == Approx(max_overlap).epsilon(1e-4));
      // Frictionless elastic: e = 1; kinetic energy e^2 back to 1e-6.
      CHECK(std::abs(res.restitution * res.restitution - 1) < 1e-6);
    }
  }
}

TEST_CASE(
    "thornton: E* and G* come from the materials (Mindlin's G*), the step is 20% of "
    "Rayleigh's",
    "[thornton]") {
  const Material steel{"steel", 7800, 210e9, 0.29, 0};
  auto p = ThorntonElastic::make({{"friction", 0.3}}, {glass, steel});
  const double e_star = 1 / ((1 - 0.09) / 70e9 + (1 - 0.29 * 0.29) / 210e9);
  const double g_glass = 70e9 / 2.6, g_steel = 210e9 / 2.58;
  const double g_star = 1 / ((2 - 0.3) / g_glass + (2 - 0.29) / g_steel);
  CHECK(p.e_star == Approx(e_star).epsilon(1e-14));
  CHECK(p.g_star == Approx(g_star).epsilon(1e-14));
  CHECK(p.friction == 0.3);
  // Identical materials: initial tangential over normal stiffness, 8 G* a / (2 E* a),
  // is Mindlin's 2(1-nu)/(2-nu) (the printed formula of the dissertation would not give it).
  auto q = elastic_params(0.3);
  CHECK(4 * q.g_star / q.e_star == Approx(2 * (1 - poisson) / (2 - poisson)).epsilon(1e-14));
  const PairScale s{1e-8, 5e-5, 1.0e-7};
  CHECK(ThorntonElastic::rule_time_step(p, s, 40) == Approx(0.2e-7).epsilon(1e-14));
  CHECK(ThorntonElastic::rule_time_step(p, s, 80) == Approx(0.1e-7).epsilon(1e-14));
  CHECK(ThorntonElastic::stability_limit(p, s) == 1.0e-7);
  auto j = ThorntonJkr::make({{"friction", 0.3}, {"surface_energy", -1}}, {glass, steel});
  CHECK(ThorntonJkr::rule_time_step(j, s, 40) == Approx(0.2e-7).epsilon(1e-14));
  CHECK(j.surface_energy == Approx(0.1));  // mean of 0.2 and 0
  CHECK(j.elastic.g_star == p.g_star);
}

TEST_CASE("thornton: make() refuses a zero Young's modulus, naming the material", "[thornton]") {
  const Material soft{"rubber_wall", 0, 0, 0.3, 0};
  using Catch::Matchers::Contains;
  CHECK_THROWS_AS(ThorntonElastic::make({{"friction", 0.3}}, {glass, soft}), InputError);
  CHECK_THROWS_WITH(ThorntonElastic::make({{"friction", 0.3}}, {glass, soft}),
                    Contains("rubber_wall") && Contains("young"));
  CHECK_THROWS_WITH(ThorntonElastic::make({{"friction", 0.3}}, {soft, glass}),
                    Contains("rubber_wall") && Contains("young"));
  CHECK_THROWS_WITH(ThorntonJkr::make({{"friction", 0.3}, {"surface_energy", -1}}, {soft, glass}),
                    Contains("rubber_wall") && Contains("young") && Contains("thornton_jkr"));
  const Material odd{"odd", 1000, 1e9, 0.7, 0};
  CHECK_THROWS_WITH(ThorntonElastic::make({{"friction", 0.3}}, {glass, odd}),
                    Contains("odd") && Contains("poisson"));
  // A negative surface energy (from the materials, or given) is refused too.
  const Material sticky{"sticky", 1000, 1e9, 0.3, -0.5};
  CHECK_THROWS_WITH(
      ThorntonJkr::make({{"friction", 0.3}, {"surface_energy", -1}}, {sticky, sticky}),
      Contains("surface_energy") && Contains("sticky"));
  CHECK_THROWS_AS(ThorntonJkr::make({{"friction", 0.3}, {"surface_energy", -0.5}}, {glass, glass}),
                  InputError);
  CHECK_NOTHROW(ThorntonElastic::make({{"friction", 0.3}}, {glass, glass}));
  // The ParamSpec lists resolve to the documented defaults.
  auto v = resolve_parameters(ThorntonJkr::parameters(), {}, "test");
  CHECK(v.at("friction") == 0.0);
  CHECK(v.at("surface_energy") == -1.0);
  CHECK(ThorntonJkr::make(v, {glass, glass}).surface_energy == 0.2);
}

TEST_CASE(
    "thornton: monotonic tangential loading at constant N follows Mindlin's curve and "
    "stops at mu N",
    "[thornton]") {
  const auto p = elastic_params(mu);
  const double r_eff = radius / 2, alpha = 1e-8;
  const double a = std::sqrt(alpha * r_eff), k0 = 8 * p.g_star * a;
  const double mu_n = mu * 4.0 / 3.0 * p.e_star * a * alpha;
  const double slide = 3 * mu_n / (2 * k0);  // delta at which the whole contact slides
  const int n = 20000;
  const double dt = 1e-9, speed = slide / n / dt;
  for (int sign : {1, -1}) {
    ThorntonElastic::History<3> h;
    auto c = state<3>(Eigen::Vector3d(0, 0, 1), alpha, Eigen::Vector3d(0, sign * speed, 0), dt,
                      1e-8, r_eff);
    double delta = 0, worst = 0;
    for (int k = 1; k <= n + 2000; ++k) {
      auto f = ThorntonElastic::force<3>(p, h, c);
      delta += speed * dt;
      REQUIRE(f.tangential.norm() <= mu_n * (1 + 1e-12));
      REQUIRE(f.tangential.x() == 0.0);
      if (k % 1000 == 0 && k <= 0.95 * n) {
        const double expected = mindlin_virgin(delta, k0, mu_n);
        worst = std::max(worst, std::abs(sign * f.tangential.y() - expected) / expected);
      }
    }
    INFO("sign " << sign << ": worst relative error " << worst);
    CHECK(worst < 1e-3);
    CHECK(std::abs(h.tangential.y()) == Approx(mu_n).epsilon(1e-9));  // full sliding
    CHECK(h.branch == ThorntonElastic::loading);
  }
}

TEST_CASE("thornton: unloading and reloading follow Masing's curves and the memory of T*",
          "[thornton]") {
  const auto p = elastic_params(mu);
  const double r_eff = radius / 2, alpha = 1e-8;
  const double a = std::sqrt(alpha * r_eff), k0 = 8 * p.g_star * a;
  const double mu_n = mu * 4.0 / 3.0 * p.e_star * a * alpha;
  const double slide = 3 * mu_n / (2 * k0);
  const double step = slide / 20000, dt = 1e-9;
  ThorntonElastic::History<2> h;
  auto c = state<2>(Eigen::Vector2d(1, 0), alpha, Eigen::Vector2d(0, step / dt), dt, 1e-8, r_eff);
  auto advance = [&](int steps) {
    for (int k = 0; k < steps; ++k) ThorntonElastic::force<2>(p, h, c);
    return h.tangential.y();
  };
  auto rel = [](double x, double y) { return std::abs(x - y) / std::abs(y); };
  // Load to delta* = 0.6 of the sliding displacement.
  const int n_load = 12000;
  const double t_star = advance(n_load);
  CHECK(rel(t_star, mindlin_virgin(n_load * step, k0, mu_n)) < 1e-3);
  // Unload: T = T* - 2 f(delta'/2) (Eq. 6.9 at constant N), to T** after 0.5 slide.
  c.tangential_velocity = Eigen::Vector2d(0, -step / dt);
  double worst = 0, t = 0;
  for (int k = 1; k <= 10000; ++k) {
    t = advance(1);
    if (k % 500 == 0)
      worst = std::max(worst, rel(t_star - t, 2 * mindlin_virgin(0.5 * k * step, k0, mu_n)));
  }
  CHECK(h.branch == ThorntonElastic::unloading);
  CHECK(h.reversal.y() == Approx(t_star).epsilon(1e-12));
  const double t_star2 = t;
  // Reload: T = T** + 2 f(delta''/2) (Eq. 6.10) until T* is back, then the virgin curve.
  c.tangential_velocity = Eigen::Vector2d(0, step / dt);
  for (int k = 1; k <= 10000; ++k) {
    t = advance(1);
    if (k % 500 == 0)
      worst = std::max(worst, rel(t - t_star2, 2 * mindlin_virgin(0.5 * k * step, k0, mu_n)));
  }
  CHECK(h.reversal2.y() == Approx(t_star2).epsilon(1e-12));
  CHECK(t == Approx(t_star).epsilon(2e-3));
  t = advance(4000);  // past T*: loading again, on the virgin curve from delta*
  CHECK(h.branch == ThorntonElastic::loading);
  worst = std::max(worst, rel(t, mindlin_virgin((n_load + 4000) * step, k0, mu_n)));
  // Full reversal: unloading from T* reaches -T* after 2 delta*, then the virgin curve.
  ThorntonElastic::History<2> g;
  std::swap(g, h);
  c.tangential_velocity = Eigen::Vector2d(0, step / dt);
  const double t1 = advance(n_load);
  c.tangential_velocity = Eigen::Vector2d(0, -step / dt);
  const double t2 = advance(2 * n_load);
  CHECK(t2 == Approx(-t1).epsilon(2e-3));
  const double t3 = advance(2000);
  CHECK(h.branch == ThorntonElastic::loading);
  worst = std::max(worst, rel(t3, mindlin_virgin(-(n_load + 2000) * step, k0, mu_n)));
  INFO("worst relative error on the Masing curves " << worst);
  CHECK(worst < 2e-3);
}

// A slip that turns back and forth by one step at constant N stays on the
// elastic line of each reversal, whatever T is: the loop closes every cycle. (A reversal ignored
// before its branch has slipped would send the next step to the virgin curve at T near T*, and each
// cycle would shed load.)
TEST_CASE("thornton: a slip turning back and forth every step keeps T", "[thornton]") {
  const auto p = elastic_params(mu);
  const double r_eff = radius / 2, alpha = 1e-8, dt = 1e-9;
  const double a = std::sqrt(alpha * r_eff), k0 = 8 * p.g_star * a;
  const double mu_n = mu * 4.0 / 3.0 * p.e_star * a * alpha;
  const double step = 0.01 * mu_n / k0;  // 1 % of mu N, elastically
  for (const double load : {0.3, 0.81}) {
    ThorntonElastic::History<3> h;
    auto c = state<3>(Eigen::Vector3d(1, 0, 0), alpha, Eigen::Vector3d(0, step / dt, 0), dt, 1e-8,
                      r_eff);
    while (h.tangential.y() < load * mu_n) ThorntonElastic::force<3>(p, h, c);
    const double loaded = h.tangential.y();
    for (int cycle = 0; cycle < 200; ++cycle) {
      c.tangential_velocity = Eigen::Vector3d(0, -step / dt, 0);
      ThorntonElastic::force<3>(p, h, c);
      c.tangential_velocity = Eigen::Vector3d(0, step / dt, 0);
      ThorntonElastic::force<3>(p, h, c);
    }
    INFO("loaded to " << loaded / mu_n << " mu N, after 200 cycles " << h.tangential.y() / mu_n);
    CHECK(h.tangential.y() == Approx(loaded).epsilon(1e-9));
  }
}

TEST_CASE(
    "thornton: the reversal values T* and T** move outwards by mu dN on slipping steps (Eq. 6.11)",
    "[thornton]") {
  const auto p = elastic_params(mu);
  const double r_eff = radius / 2, dt = 1e-9;
  const auto mu_n = [&](double alpha) {
    return mu * 4.0 / 3.0 * p.e_star * std::sqrt(r_eff) * alpha * std::sqrt(alpha);
  };
  const double step = 1e-12;  // tangential displacement per step, m
  ThorntonElastic::History<2> h;
  auto c = state<2>(Eigen::Vector2d(1, 0), 1e-8, Eigen::Vector2d(0, step / dt), dt, 1e-8, r_eff);
  for (int k = 0; k < 5000; ++k) ThorntonElastic::force<2>(p, h, c);
  REQUIRE(h.tangential.y() == Approx(mu_n(1e-8)).epsilon(1e-12));  // sliding
  // Unload by one step: T* = T.
  c.tangential_velocity = Eigen::Vector2d(0, -step / dt);
  ThorntonElastic::force<2>(p, h, c);
  REQUIRE(h.branch == ThorntonElastic::unloading);
  const double star = h.reversal.y();
  CHECK(star == Approx(mu_n(1e-8)).epsilon(1e-12));
  // Raise N with no slip (Eq. 6.7's no-slip solution, theta = 1): the slip
  // annulus does not change, nor does T* (Eq. 6.11 acts on the steps that
  // slip), nor T.
  c.tangential_velocity.setZero();
  const double t_before = h.tangential.y();
  c.overlap = 1.5e-8;
  ThorntonElastic::force<2>(p, h, c);
  CHECK(h.reversal.y() == star);
  CHECK(h.tangential.y() == t_before);
  // Unload some more (slipping, theta < 1 by Eq. 6.9); raising N a little on
  // such a step (mu dN below 8 G* a |slip|: no Eq. 6.7) moves T* out by mu dN.
  c.tangential_velocity = Eigen::Vector2d(0, -step / dt);
  for (int k = 0; k < 2000; ++k) ThorntonElastic::force<2>(p, h, c);
  REQUIRE(h.branch == ThorntonElastic::unloading);
  const double star0 = h.reversal.y();
  c.overlap = 1.5001e-8;
  ThorntonElastic::force<2>(p, h, c);
  CHECK(h.reversal.y() == Approx(star0 + mu_n(1.5001e-8) - mu_n(1.5e-8)).epsilon(1e-12));
  CHECK(h.reversal.y() > star0);
  // Reload: T** = T; a slipping step that lowers N moves T** up and T* down.
  c.tangential_velocity = Eigen::Vector2d(0, step / dt);
  for (int k = 0; k < 500; ++k) ThorntonElastic::force<2>(p, h, c);
  REQUIRE(h.branch == ThorntonElastic::reloading);
  const double star1 = h.reversal.y(), star2 = h.reversal2.y();
  REQUIRE(star2 < 0.5 * star1);
  c.overlap = 1.5e-8;
  ThorntonElastic::force<2>(p, h, c);
  const double mu_dn = mu_n(1.5e-8) - mu_n(1.5001e-8);
  CHECK(h.reversal.y() == Approx(star1 + mu_dn).epsilon(1e-12));
  CHECK(h.reversal2.y() == Approx(star2 - mu_dn).epsilon(1e-12));
}

TEST_CASE(
    "thornton: with no tangential motion T follows N down (|T| <= mu N), and stays put as N "
    "rises",
    "[thornton]") {
  const auto p = elastic_params(mu);
  const double r_eff = radius / 2, dt = 1e-9;
  ThorntonElastic::History<3> h;
  auto c = state<3>(Eigen::Vector3d(1, 0, 0), 2e-8, Eigen::Vector3d(0, 0.3, 0.4), dt, 1e-8, r_eff);
  for (int k = 0; k < 20000; ++k) ThorntonElastic::force<3>(p, h, c);
  const auto hertz = [&](double alpha) {
    return 4.0 / 3.0 * p.e_star * std::sqrt(r_eff) * alpha * std::sqrt(alpha);
  };
  REQUIRE(h.tangential.norm() == Approx(mu * hertz(2e-8)).epsilon(1e-9));  // sliding
  const Eigen::Vector3d direction = h.tangential.normalized();
  c.tangential_velocity.setZero();
  // Rising N with no slip: no-slip branch (Eq. 6.7), T unchanged.
  c.overlap = 3e-8;
  const Eigen::Vector3d before = h.tangential;
  ThorntonElastic::force<3>(p, h, c);
  CHECK((h.tangential - before).norm() <= 1e-15 * before.norm());
  // Falling N with no slip, down to nothing: always inside the cone.
  for (int k = 0; k <= 3000; ++k) {
    c.overlap = 3e-8 * (1 - k / 3000.0) + 1e-30;
    auto f = ThorntonElastic::force<3>(p, h, c);
    REQUIRE(std::isfinite(f.normal));
    REQUIRE(f.tangential.allFinite());
    REQUIRE(finite_history(h));
    REQUIRE(f.tangential.norm() <= mu * f.normal * (1 + 1e-12) + 1e-300);
    if (f.tangential.norm() > 0) REQUIRE(f.tangential.normalized().dot(direction) > 1 - 1e-12);
  }
  // N = 0 exactly and a contact that ends: no NaN, nothing left.
  c.overlap = 0;
  auto f = ThorntonElastic::force<3>(p, h, c);
  CHECK(f.normal == 0.0);
  CHECK(f.tangential.norm() == 0.0);
  CHECK(h.tangential.norm() == 0.0);
}

TEMPLATE_TEST_CASE_SIG(
    "thornton: oblique elastic impacts keep |T| <= mu N, the tangential force "
    "reverses above the friction angle unless the spheres slide throughout",
    "[thornton]", ((int D), D), 2, 3) {
  // Dissertation 6.4: friction angle atan(0.35) = 19 degrees. At 15 degrees sliding
  // only comes at the end; from 30 degrees the spheres slide from the start, T
  // falls, reverses and slides again; at 75 degrees they slide throughout with no
  // reversal (rigid-sphere theory: sliding throughout for tan(theta) > 7 mu).
  const auto p = elastic_params(mu);
  for (double angle : {15.0, 30.0, 45.0, 60.0, 75.0}) {
    TwoSpheres<ThorntonElastic, D> s(p, 0.1, angle, 1e-10);
    double t_pos = 0, t_neg = 0, sign = 0;
    long steps = 0, sliding = 0, sliding_first_quarter = 0;
    std::vector<char> slid;
    bool seen = false;
    for (long k = 0; k < 1000000; ++k) {
      s.step();
      if (!s.in_contact) {
        if (seen) break;
        continue;
      }
      seen = true;
      ++steps;
      const double limit = mu * s.f.normal;
      REQUIRE(s.f.tangential.norm() <= limit * (1 + 1e-12) + 1e-300);
      REQUIRE(finite_history(s.h));
      double t = s.tangential_component();
      if (sign == 0 && t != 0) sign = t > 0 ? 1 : -1;
      t *= sign;
      t_pos = std::max(t_pos, t);
      t_neg = std::min(t_neg, t);
      slid.push_back(s.f.tangential.norm() >= limit * (1 - 1e-9));
    }
    for (std::size_t k = 0; k < slid.size(); ++k) {
      sliding += slid[k];
      if (k < slid.size() / 4) sliding_first_quarter += slid[k];
    }
    INFO("D=" << D << " angle " << angle << ": steps " << steps << ", sliding " << sliding
              << ", T from " << t_neg << " to " << t_pos);
    REQUIRE(steps > 5000);
    // At 60 degrees the reversed force peaks at 6% of the forward one; round-off
    // is 1e-12 of it, so 1% is a safe threshold.
    const bool reverses = t_neg < -0.01 * t_pos;
    if (angle == 15.0) {
      CHECK(sliding_first_quarter == 0);  // microslip only, sliding comes late
      CHECK(sliding > 0);
    } else if (angle < 70) {
      CHECK(reverses);
      CHECK(slid[1] != 0);  // rigid-body sliding from the start
    } else {
      CHECK_FALSE(reverses);
      CHECK(t_neg == 0.0);
      CHECK(sliding == steps);
    }
  }
}

TEMPLATE_TEST_CASE_SIG(
    "thornton: oblique JKR impacts peel, then slide, |T| stays below Tc while "
    "peeling and below the sliding force after",
    "[thornton][jkr]", ((int D), D), 2, 3) {
  // Dissertation 6.4 with gamma = 0.2 J/m^2: except at small angles (15 degrees)
  // the contact peels while the normal force is still rising, and peeling lets T
  // exceed mu N before it falls to the sliding force.
  const double gamma = 0.2;
  const auto p = jkr_params(mu, gamma);
  const double e = p.elastic.e_star, g = p.elastic.g_star;
  const double nc = ThorntonJkr::pull_off_force(gamma, radius / 2);
  const double alpha_f = ThorntonJkr::separation_overlap(gamma, radius / 2, e);
  for (double angle : {15.0, 30.0, 45.0, 60.0, 75.0}) {
    TwoSpheres<ThorntonJkr, D> s(p, 0.1, angle, 1e-10);
    bool seen = false;
    double last_overlap = 0;
    std::vector<double> normal, tangential;
    long first_peeled = -1;
    for (long k = 0; k < 1000000; ++k) {
      s.step();
      if (!s.in_contact) {
        if (seen) break;
        continue;
      }
      seen = true;
      last_overlap = s.c.overlap;
      const double n = s.f.normal, t = s.f.tangential.norm();
      REQUIRE(std::isfinite(n));
      REQUIRE(s.f.tangential.allFinite());
      REQUIRE(n >= -nc * (1 + 1e-9));
      if (s.h.peeled) {
        REQUIRE(t <= ThorntonJkr::sliding_force(mu, n, nc) * (1 + 1e-12));
      } else {
        REQUIRE(t <= 4 * std::sqrt(g / e * nc * (n + nc)) * (1 + 1e-12));
      }
      if (s.h.peeled && first_peeled < 0) first_peeled = static_cast<long>(normal.size());
      normal.push_back(n);
      tangential.push_back(t);
    }
    const long steps = static_cast<long>(normal.size());
    const long peak = std::max_element(normal.begin(), normal.end()) - normal.begin();
    double ratio = 0;  // max T / (mu N) while N is above a tenth of its peak
    for (long k = 0; k < steps; ++k)
      if (normal[k] > 0.1 * normal[peak]) ratio = std::max(ratio, tangential[k] / (mu * normal[k]));
    INFO("D=" << D << " angle " << angle << ": steps " << steps << ", peeled at step "
              << first_peeled << ", N peaks at " << peak << ", max T/(mu N) " << ratio);
    REQUIRE(steps > 5000);
    // The contact ended at the JKR separation point, not at zero overlap.
    CHECK(last_overlap < 0);
    CHECK(last_overlap > alpha_f);
    if (angle == 15.0) {
      CHECK((first_peeled < 0 || first_peeled > peak));
    } else {
      CHECK(first_peeled >= 0);
      CHECK(first_peeled < peak);
      CHECK(ratio > 1.2);
    }
  }
}

TEST_CASE(
    "thornton: JKR contact radius at zero load is a0 = (9 pi Gamma R*^2/(2 E*))^{1/3}, the "
    "contact snaps on at -8/9 Nc",
    "[thornton][jkr]") {
  const auto p = jkr_params(mu, 0.2);
  const double r_eff = radius / 2, gamma = 0.2, e = p.elastic.e_star;
  const double a0 = std::cbrt(9 * pi * gamma * r_eff * r_eff / (2 * e));
  const double alpha0 = a0 * a0 / (3 * r_eff);  // Eq. 6.14 at a0
  const double nc = 1.5 * pi * gamma * r_eff;
  REQUIRE(ThorntonJkr::zero_load_radius(gamma, r_eff, e) == Approx(a0).epsilon(1e-14));
  ThorntonJkr::History<2> h;
  auto c = state<2>(Eigen::Vector2d(1, 0), 0, Eigen::Vector2d::Zero(), 1e-9, 1e-8, r_eff);
  const double step = alpha0 / 9973.3;  // a grid that does not land on alpha0
  c.overlap = 1e-6 * step;
  REQUIRE(ThorntonJkr::touching(p, h, c.overlap));
  auto f = ThorntonJkr::force<2>(p, h, c);
  // Snap-on: a^3 = 2 pi Gamma R*^2/E* at alpha = 0, N = -8/9 Nc.
  CHECK(h.contact_radius == Approx(std::cbrt(2 * pi * gamma * r_eff * r_eff / e)).epsilon(1e-6));
  CHECK(f.normal == Approx(-8.0 / 9.0 * nc).epsilon(1e-5));
  double previous = f.normal, previous_a = h.contact_radius, previous_alpha = c.overlap;
  bool crossed = false;
  for (int k = 1; k < 30000 && !crossed; ++k) {
    c.overlap = k * step;
    f = ThorntonJkr::force<2>(p, h, c);
    if (f.normal >= 0) {
      // Interpolate the zero crossing between the two steps.
      const double w = -previous / (f.normal - previous);
      const double a_zero = previous_a + w * (h.contact_radius - previous_a);
      const double alpha_zero = previous_alpha + w * (c.overlap - previous_alpha);
      INFO("a at N = 0: " << a_zero << " vs a0 " << a0);
      CHECK(a_zero == Approx(a0).epsilon(1e-4));
      CHECK(alpha_zero == Approx(alpha0).epsilon(1e-4));
      crossed = true;
    }
    REQUIRE(f.normal >= previous);  // loading: N rises monotonically with alpha
    previous = f.normal;
    previous_a = h.contact_radius;
    previous_alpha = c.overlap;
  }
  CHECK(crossed);
}

TEST_CASE(
    "thornton: JKR pull-off force is -Nc = -1.5 pi Gamma R*, the contact separates at "
    "alpha_f = -(3/4)(pi^2 Gamma^2 R*/E*^2)^{1/3} where N = -5/9 Nc",
    "[thornton][jkr]") {
  for (double gamma : {0.2, 0.02, 2.0}) {
    const auto p = jkr_params(mu, gamma);
    const double r_eff = radius / 2, e = p.elastic.e_star;
    const double nc = 1.5 * pi * gamma * r_eff;
    const double alpha_f = -0.75 * std::cbrt(pi * pi * gamma * gamma * r_eff / (e * e));
    const double a0 = std::cbrt(9 * pi * gamma * r_eff * r_eff / (2 * e));
    const double alpha0 = a0 * a0 / (3 * r_eff);
    ThorntonJkr::History<3> h;
    auto c =
        state<3>(Eigen::Vector3d(0, 1, 0), 2 * alpha0, Eigen::Vector3d::Zero(), 1e-9, 1e-8, r_eff);
    ThorntonJkr::force<3>(p, h, c);
    const double step = alpha0 / 20000;
    double min_normal = 0, last_normal = 0, last_alpha = 0;
    int k = 0;
    for (; k < 1000000; ++k) {
      c.overlap = 2 * alpha0 - k * step;
      if (!ThorntonJkr::touching(p, h, c.overlap)) break;
      auto f = ThorntonJkr::force<3>(p, h, c);
      REQUIRE(std::isfinite(f.normal));
      min_normal = std::min(min_normal, f.normal);
      last_normal = f.normal;
      last_alpha = c.overlap;
    }
    INFO("gamma " << gamma << ": min N / Nc = " << min_normal / nc << ", last N / Nc "
                  << last_normal / nc << ", separated at " << c.overlap << " (alpha_f " << alpha_f
                  << ")");
    CHECK(min_normal == Approx(-nc).epsilon(1e-6));
    CHECK(ThorntonJkr::pull_off_force(gamma, r_eff) == Approx(nc).epsilon(1e-14));
    CHECK(ThorntonJkr::separation_overlap(gamma, r_eff, e) == Approx(alpha_f).epsilon(1e-14));
    // Separation within one step of alpha_f. N - N(alpha_f) grows like sqrt(alpha -
    // alpha_f) (alpha(a) has a double root there), so one step of alpha0/20000 before
    // it N is still 1% off -5/9 Nc; 1e-12 alpha_f before it, 1e-6 off.
    CHECK(last_alpha > alpha_f);
    CHECK(c.overlap <= alpha_f);
    CHECK(last_alpha - alpha_f <= step);
    CHECK(last_normal == Approx(-5.0 / 9.0 * nc).epsilon(0.02));
    ThorntonJkr::History<3> edge;
    c.overlap = alpha0;
    ThorntonJkr::force<3>(p, edge, c);
    c.overlap = alpha_f * (1 - 1e-12);
    REQUIRE(ThorntonJkr::touching(p, edge, c.overlap));
    auto f_edge = ThorntonJkr::force<3>(p, edge, c);
    CHECK(f_edge.normal == Approx(-5.0 / 9.0 * nc).epsilon(1e-5));
    CHECK(edge.contact_radius ==
          Approx(std::cbrt(pi * gamma * r_eff * r_eff / (8 * e))).epsilon(1e-5));
    // Once separated, a small negative overlap does not re-form the contact.
    h = {};
    CHECK_FALSE(ThorntonJkr::touching(p, h, 0.5 * alpha_f));
    CHECK_FALSE(ThorntonJkr::touching(p, h, 0.0));
    CHECK(ThorntonJkr::touching(p, h, 1e-15));
  }
}

TEST_CASE(
    "thornton: a JKR contact whose R* changes (a sphere along a cone) separates at the "
    "alpha_f of its present R*, with the force of that R*",
    "[thornton][jkr]") {
  const double gamma = 0.2;
  const auto p = jkr_params(mu, gamma);
  const double e = p.elastic.e_star;
  const double r_big = radius, r_small = radius / 2;
  const double f_big = ThorntonJkr::separation_overlap(gamma, r_big, e);
  const double f_small = ThorntonJkr::separation_overlap(gamma, r_small, e);
  REQUIRE(f_big < f_small);  // alpha_f ~ -R*^{1/3}: a larger R* holds on to a wider gap
  const double between = 0.5 * (f_big + f_small);
  // Touches at R* = r_first and is pulled out to `to` in 100 steps.
  auto touch_then_pull = [&](double r_first, double to, ThorntonJkr::History<3>& h) {
    auto c = state<3>(Eigen::Vector3d(0, 1, 0), 1e-8, Eigen::Vector3d::Zero(), 1e-9, 1e-8, r_first);
    ThorntonJkr::force<3>(p, h, c);
    for (int k = 1; k <= 100; ++k) {
      c.overlap = 1e-8 + k * (to - 1e-8) / 100;
      ThorntonJkr::force<3>(p, h, c);
    }
    return c;
  };
  // Moving onto a smaller R*: at `between` the contact is past its new alpha_f, so it ends.
  ThorntonJkr::History<3> shrinking;
  auto c = touch_then_pull(r_big, between, shrinking);
  REQUIRE(shrinking.contact_radius > 0);
  c.effective_radius = r_small;
  const auto gone = ThorntonJkr::force<3>(p, shrinking, c);
  CHECK(gone.normal == 0);
  CHECK(shrinking.contact_radius == 0);
  CHECK_FALSE(ThorntonJkr::touching(p, shrinking, between));
  // Moving onto a larger R*, then pulled to a gap the first R* could not hold: it lasts,
  // its force that of a contact of the larger R* all along (the same path at r_big).
  ThorntonJkr::History<3> growing, direct;
  auto g = touch_then_pull(r_small, 0.5 * f_small, growing);
  auto d = touch_then_pull(r_big, 0.5 * f_small, direct);
  REQUIRE(growing.contact_radius > 0);
  g.effective_radius = r_big;
  for (int k = 1; k <= 50; ++k) {
    g.overlap = d.overlap = 0.5 * f_small + k * (between - 0.5 * f_small) / 50;
    REQUIRE(ThorntonJkr::touching(p, growing, g.overlap));
    const auto fg = ThorntonJkr::force<3>(p, growing, g);
    const auto fd = ThorntonJkr::force<3>(p, direct, d);
    CHECK(fg.normal == Approx(fd.normal).epsilon(1e-9));
  }
  CHECK(growing.contact_radius > 0);
  CHECK(growing.separation_overlap == Approx(f_big).epsilon(1e-14));
}

TEST_CASE(
    "thornton: a JKR impact loses the work of the separation loop, 7.09 (Gamma^5 R*^4/E*^2)^{1/3}, "
    "and sticks below the matching velocity",
    "[thornton][jkr]") {
  const double gamma = 0.2, r_eff = radius / 2, m_eff = sphere_mass(radius, density) / 2;
  const auto p = jkr_params(0.0, gamma);
  const double e = p.elastic.e_star;
  // W = -int_{alpha_f}^{0} N d(alpha) along the stable branch, by Simpson's rule in a.
  const double k = std::sqrt(2 * pi * gamma / e);
  const double a_f = std::cbrt(pi * gamma * r_eff * r_eff / (8 * e));
  const double a_zero = std::cbrt(2 * pi * gamma * r_eff * r_eff / e);
  auto integrand = [&](double a) {
    const double n = 4 * e * a * a * a / (3 * r_eff) - std::sqrt(8 * pi * gamma * e * a * a * a);
    return -n * (2 * a / r_eff - 0.5 * k / std::sqrt(a));
  };
  const int panels = 20000;
  const double h_a = (a_zero - a_f) / panels;
  double work = integrand(a_f) + integrand(a_zero);
  for (int i = 1; i < panels; ++i) work += (i % 2 ? 4 : 2) * integrand(a_f + i * h_a);
  work *= h_a / 3;
  // Thornton and Ning (1998): the same work in closed form.
  CHECK(work ==
        Approx(7.09 * std::cbrt(std::pow(gamma, 5) * std::pow(r_eff, 4) / (e * e))).epsilon(1e-3));
  const double v_stick = std::sqrt(2 * work / m_eff);
  for (double ratio : {1.2, 2.0, 5.0}) {
    const double v = ratio * v_stick;
    const double dt = 2e-11;
    auto res = normal_impact<ThorntonJkr, 3>(p, m_eff, r_eff, v, dt, 2000000);
    INFO("v = " << ratio << " v_stick");
    REQUIRE(res.separated);
    REQUIRE(res.finite);
    const double expected = std::sqrt(1 - 1 / (ratio * ratio));
    CHECK(res.restitution == Approx(expected).epsilon(2e-3));
    CHECK(res.min_normal == Approx(-1.5 * pi * gamma * r_eff).epsilon(1e-3));
  }
  // Below v_stick the spheres stay together (elastic JKR has no damping: they ring).
  auto res = normal_impact<ThorntonJkr, 2>(p, m_eff, r_eff, 0.9 * v_stick, 2e-11, 2000000);
  CHECK_FALSE(res.separated);
  CHECK(res.finite);
}

// Gamma = 0 hands the step to thornton_elastic, so the two agree to round-off:
// bit for bit when the compiler rounds each operation on its own, within a few
// units of the last place when it fuses multiply-adds (the default -march=native
// build may fuse them differently where the shared code is inlined). The
// bound, 1e-12 of the largest force over the whole impact, is far below any
// model difference (a Gamma of 1e-10 J/m^2 already moves N by ~1e-6 of it).
TEST_CASE("thornton: JKR with Gamma = 0 is thornton_elastic to round-off", "[thornton][jkr]") {
  const auto pe = elastic_params(mu);
  const auto pj = jkr_params(mu, 0.0);
  for (double angle : {10.0, 40.0, 80.0}) {
    TwoSpheres<ThorntonElastic, 3> a(pe, 0.5, angle, 2e-10);
    TwoSpheres<ThorntonJkr, 3> b(pj, 0.5, angle, 2e-10);
    long steps = 0;
    double force_scale = 0, normal_gap = 0, tangential_gap = 0, position_gap = 0;
    for (long k = 0; k < 100000; ++k) {
      a.step();
      b.step();
      REQUIRE(a.in_contact == b.in_contact);
      force_scale = std::max(force_scale, std::abs(a.f.normal));
      normal_gap = std::max(normal_gap, std::abs(a.f.normal - b.f.normal));
      tangential_gap = std::max(tangential_gap, (a.f.tangential - b.f.tangential).norm());
      position_gap = std::max(position_gap, (a.x[0] - b.x[0]).norm());
      steps += a.in_contact;
      if (steps > 0 && !a.in_contact) break;
    }
    INFO("angle " << angle << ": largest N " << force_scale << " N, gaps N " << normal_gap << " T "
                  << tangential_gap << " N, x " << position_gap << " m");
    CHECK(force_scale > 0);
    CHECK(normal_gap <= 1e-12 * force_scale);
    CHECK(tangential_gap <= 1e-12 * force_scale);
    CHECK(position_gap <= 1e-12 * radius);
    CHECK(steps > 1000);
  }
  // And a small Gamma tends to Hertz continuously (the JKR path, not the shortcut).
  // At fixed overlap the O(sqrt(Gamma)) terms of a and N cancel; expanding Eq. 6.14
  // and the JKR force to second order gives N = N_Hertz - (2/3) Nc, with a relative
  // correction of order (kR*/a^{3/2}) (5e-4 for Gamma = 1e-6 here).
  const double r_eff = radius / 2, alpha = 1e-8;
  const double hertz = 4.0 / 3.0 * pe.e_star * std::sqrt(r_eff) * alpha * std::sqrt(alpha);
  for (double gamma : {1e-6, 1e-8, 1e-10}) {
    const auto p = jkr_params(mu, gamma);
    ThorntonJkr::History<2> h;
    auto c = state<2>(Eigen::Vector2d(1, 0), alpha, Eigen::Vector2d::Zero(), 1e-9, 1e-8, r_eff);
    auto f = ThorntonJkr::force<2>(p, h, c);
    const double nc = 1.5 * pi * gamma * r_eff;
    INFO("gamma " << gamma << ": (N - N_Hertz)/Nc = " << (f.normal - hertz) / nc);
    CHECK((f.normal - hertz) / nc == Approx(-2.0 / 3.0).epsilon(2e-3));
  }
}

TEST_CASE(
    "thornton: JKR tangential force peels at 8 G* a (Eq. 6.19) up to Tc (Eq. 6.21), then "
    "slides at Eq. 6.25 or, below -0.3 Nc, Eq. 6.23",
    "[thornton][jkr]") {
  const double gamma = 0.2, r_eff = radius / 2;
  const double nc = 1.5 * pi * gamma * r_eff;
  const double dt = 1e-9;
  auto pj = jkr_params(mu, gamma);
  const double e = pj.elastic.e_star, g = pj.elastic.g_star;
  const double a0 = ThorntonJkr::zero_load_radius(gamma, r_eff, e);
  // Eq. 6.14 for the overlap at a given contact radius.
  auto overlap_at = [&](double a) { return a * a / r_eff - std::sqrt(2 * pi * gamma * a / e); };
  struct Case {
    double a_over_a0, friction;
  };
  for (Case cs : {Case{1.2, 0.35}, Case{1.2, 3.0}, Case{0.75, 0.35}, Case{0.75, 3.0}}) {
    auto p = jkr_params(cs.friction, gamma);
    ThorntonJkr::History<3> h;
    auto c = state<3>(Eigen::Vector3d(0, 0, -1), 2 * overlap_at(a0), Eigen::Vector3d::Zero(), dt,
                      1e-8, r_eff);
    ThorntonJkr::force<3>(p, h, c);  // form the contact with a positive overlap
    c.overlap = overlap_at(cs.a_over_a0 * a0);
    const double normal = ThorntonJkr::force<3>(p, h, c).normal;
    REQUIRE(h.contact_radius == Approx(cs.a_over_a0 * a0).epsilon(1e-9));
    // Thornton's criteria, written out again here.
    const double t_c = 4 * std::sqrt(g / e * (normal * nc + nc * nc));
    double slide;
    if (normal < -0.3 * nc) {
      const double n1 = normal + 2 * nc + 2 * std::sqrt(normal * nc + nc * nc);
      slide = cs.friction * n1 * std::pow(1 - (n1 - normal) / (3 * n1), 1.5);
    } else {
      slide = cs.friction * (normal + 2 * nc);
    }
    INFO("a/a0 " << cs.a_over_a0 << " mu " << cs.friction << ": N/Nc " << normal / nc << ", Tc/Nc "
                 << t_c / nc << ", sliding/Nc " << slide / nc);
    REQUIRE((cs.a_over_a0 < 1) == (normal < -0.3 * nc));
    // First increment: no slip, stiffness 8 G* a with a the unpeeled JKR radius.
    const double step = t_c / (8 * g * h.contact_radius) / 5000;
    c.tangential_velocity = Eigen::Vector3d(step / dt, 0, 0);
    auto f = ThorntonJkr::force<3>(p, h, c);
    CHECK(f.tangential.x() == Approx(8 * g * h.contact_radius * step).epsilon(1e-9));
    CHECK(f.normal == normal);
    double t_peel = 0;
    for (int k = 0; k < 100000 && !h.peeled; ++k) {
      t_peel = f.tangential.norm();
      f = ThorntonJkr::force<3>(p, h, c);
    }
    REQUIRE(h.peeled);
    // Peeling ended when T reached Tc (within one increment).
    CHECK(t_peel == Approx(t_c).epsilon(2e-3));
    CHECK(t_peel < t_c);
    CHECK(f.tangential.norm() == Approx(std::min(t_c, slide)).epsilon(1e-12));
    if (t_c < slide && normal >= -0.3 * nc) {
      // Partial slip after peeling: with no tangential motion, lowering N lowers T by
      // mu dN (1 - theta), Eqs. 6.6 and 6.8 with N + 2Nc; raising it again changes
      // nothing (no slip, Eq. 6.7).
      const Eigen::Vector3d moving = c.tangential_velocity;
      c.tangential_velocity.setZero();
      const double t_before = f.tangential.norm();
      c.overlap = overlap_at(1.1 * a0);
      f = ThorntonJkr::force<3>(p, h, c);
      const double mu_dn = cs.friction * (f.normal - normal);
      const double theta = std::cbrt(1 - (t_before + mu_dn) / (cs.friction * (f.normal + 2 * nc)));
      REQUIRE(mu_dn < 0);
      CHECK(f.tangential.norm() == Approx(t_before + mu_dn * (1 - theta)).epsilon(1e-12));
      CHECK(f.tangential.norm() < t_before);
      const double t_low = f.tangential.norm();
      c.overlap = overlap_at(1.2 * a0);
      f = ThorntonJkr::force<3>(p, h, c);
      CHECK(f.tangential.norm() == t_low);
      c.tangential_velocity = moving;
    }
    // Keep sliding: the force settles on the sliding criterion and never exceeds it.
    for (int k = 0; k < 200000; ++k) {
      f = ThorntonJkr::force<3>(p, h, c);
      REQUIRE(f.tangential.norm() <= slide * (1 + 1e-12));
    }
    CHECK(f.tangential.norm() == Approx(slide).epsilon(1e-9));
    CHECK(f.tangential.y() == 0.0);
    CHECK(f.tangential.z() == 0.0);
  }
}

TEMPLATE_TEST_CASE_SIG(
    "thornton: no NaN or infinity at pull-off, N -> 0, zero slip, or contacts "
    "that break and re-form every few steps",
    "[thornton][jkr]", ((int D), D), 2, 3) {
  const double r_eff = radius / 2, dt = 1e-9;
  std::mt19937 rng(12345 + D);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (double gamma : {0.0, 1e-12, 0.2, 5.0}) {
    for (double friction : {0.0, mu, 2.0}) {
      const auto p = jkr_params(friction, gamma);
      const auto pe = elastic_params(friction);
      const double e = p.elastic.e_star;
      const double alpha_f = ThorntonJkr::separation_overlap(gamma, r_eff, e);
      const double nc = ThorntonJkr::pull_off_force(gamma, r_eff);
      const double scale = gamma > 0 ? std::max(-alpha_f, 1e-12) : 1e-9;
      ThorntonJkr::History<D> h;
      ThorntonElastic::History<D> he;
      long contacts = 0, breaks = 0;
      bool was = false;
      double overlap = 0.5 * scale;
      Vec<D> normal = planar<D>(1, 0);
      for (int k = 0; k < 20000; ++k) {
        // Every few steps, jump somewhere between well apart and well pressed, often
        // right at the edges: alpha_f, 0, the zero-load point, exactly 0.
        if (k % 5 == 0) {
          const double u = unit(rng);
          if (u < 0.15)
            overlap = alpha_f * (1 + 1e-12 * (unit(rng) - 0.5));
          else if (u < 0.25)
            overlap = 0.0;
          else if (u < 0.3)
            overlap = 1e-300;
          else
            overlap = scale * (-2 + 5 * unit(rng));
        } else {
          overlap += scale * 0.1 * (unit(rng) - 0.5);
        }
        // Tangential motion: none, tiny, or large, in any in-plane direction; the
        // normal turns a little too (3D: out of the x-y plane).
        Vec<D> vt = Vec<D>::Zero();
        const double kind = unit(rng);
        if (kind > 0.3) {
          for (int i = 0; i < D; ++i) vt[i] = unit(rng) - 0.5;
          vt *= (kind > 0.9 ? 1e-12 : 0.5) / std::max(vt.norm(), 1e-300);
        }
        Vec<D> turn = Vec<D>::Zero();
        for (int i = 0; i < D; ++i) turn[i] = 0.02 * (unit(rng) - 0.5);
        normal = (normal + turn).normalized();
        vt -= normal * normal.dot(vt);
        auto c = state<D>(normal, overlap, vt, dt, 1e-8, r_eff);
        if (ThorntonJkr::touching(p, h, overlap)) {
          ++contacts;
          was = true;
          auto f = ThorntonJkr::force<D>(p, h, c);
          REQUIRE(std::isfinite(f.normal));
          REQUIRE(f.tangential.allFinite());
          REQUIRE(finite_history(h));
          REQUIRE(f.normal >= -nc * (1 + 1e-9));
          // In the tangent plane (the input's own rounding, ~1e-16 of the slip, can be
          // amplified when a large trial force is scaled down to a tiny cap).
          REQUIRE(std::abs(f.tangential.dot(normal)) <= 1e-6 * f.tangential.norm() + 1e-300);
          // Peeling may hold up to Tc, sliding at most the sliding force.
          const double t_c =
              4 * std::sqrt(std::max(0.0, p.elastic.g_star / e * nc * (f.normal + nc)));
          const double limit =
              gamma > 0 ? std::max(t_c, ThorntonJkr::sliding_force(friction, f.normal, nc))
                        : friction * f.normal;
          REQUIRE(f.tangential.norm() <= limit * (1 + 1e-9) + 1e-300);
        } else {
          if (was) ++breaks;
          was = false;
          h = {};
        }
        if (ThorntonElastic::touching(pe, he, overlap)) {
          auto f = ThorntonElastic::force<D>(pe, he, c);
          REQUIRE(std::isfinite(f.normal));
          REQUIRE(f.tangential.allFinite());
          REQUIRE(finite_history(he));
          REQUIRE(f.tangential.norm() <= friction * f.normal * (1 + 1e-12) + 1e-300);
        } else {
          he = {};
        }
      }
      INFO("gamma " << gamma << " mu " << friction);
      CHECK(contacts > 1000);
      CHECK(breaks > 100);
    }
  }
}

TEST_CASE("thornton: adhesive contacts outlast zero overlap, so the skin must cover the JKR reach",
          "[thornton][jkr]") {
  // Soft, sticky, large particles: alpha_f = -(3/4)(pi^2 Gamma^2 R*/E*^2)^(1/3).
  const double gamma = 5.0, r = 1e-3, young = 1e6, nu = 0.3;
  auto scene = [&](Simulation<3>& sim) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"gel", 1000, young, nu, gamma});
    sim.set_contact("gel", "gel", "thornton_jkr", {{"friction", 0.3}});
    ParticleSpec a, b;
    a.radius = b.radius = r, a.material = b.material = 0;
    b.position = {2.5 * r, 0, 0};
    sim.add_particle(a), sim.add_particle(b);
  };
  const double e_star = young / (2 * (1 - nu * nu));
  const double reach = 0.75 * std::cbrt(pi * pi * gamma * gamma * r / (e_star * e_star));
  Simulation<3> tiny;
  scene(tiny);
  tiny.set_skin(0.5 * reach);
  CHECK_THROWS_WITH(tiny.prepare(), Catch::Contains("too small for the adhesive contacts"));
  Simulation<3> automatic;
  scene(automatic);
  automatic.prepare();
  CHECK(automatic.skin() > 1.5 * reach);
}

// A surface energy ramped up from zero while a contact carries T (the
// agglomerate preparation's ramps): where T already reaches Tc of the new Gamma
// (Eq. 6.21) the contact counts as peeled and keeps T, with the sliding limit
// mu (N + 2Nc) of Eq. 6.25 ahead of it; below Tc it goes on peeling from T.
// Taken as a fresh contact it lost T down to Tc in one step.
TEST_CASE("thornton: a surface energy switched on under a sheared contact keeps its T",
          "[thornton][jkr]") {
  const double r_eff = radius / 2, dt = 1e-9, overlap = 1e-8;
  for (double gamma : {1e-4, 0.2}) {
    const auto p0 = jkr_params(mu, 0.0), p1 = jkr_params(mu, gamma);
    ThorntonJkr::History<3> h;
    auto c = state<3>(Eigen::Vector3d(0, 0, -1), overlap, Eigen::Vector3d::Zero(), dt, 1e-8, r_eff);
    auto f = ThorntonJkr::force<3>(p0, h, c);
    const double limit = mu * f.normal;
    c.tangential_velocity = Eigen::Vector3d(1e-3, 0, 0);
    for (int k = 0; k < 100000 && f.tangential.norm() < 0.5 * limit; ++k)
      f = ThorntonJkr::force<3>(p0, h, c);
    const double t0 = f.tangential.norm();
    REQUIRE(t0 == Approx(0.5 * limit).epsilon(0.05));
    c.tangential_velocity.setZero();
    f = ThorntonJkr::force<3>(p1, h, c);
    const double nc = 1.5 * pi * gamma * r_eff;
    const double t_c = 4 * std::sqrt(p1.elastic.g_star / p1.elastic.e_star * nc * (f.normal + nc));
    INFO("gamma " << gamma << ": T " << t0 << " N, Tc " << t_c << " N");
    CHECK(h.peeled == (t0 >= t_c));
    CHECK(f.tangential.norm() == Approx(t0).epsilon(1e-12));
    // Sheared on, it reaches the sliding force of the adhesive contact.
    c.tangential_velocity = Eigen::Vector3d(1e-3, 0, 0);
    for (int k = 0; k < 200000; ++k) f = ThorntonJkr::force<3>(p1, h, c);
    CHECK(h.peeled);
    CHECK(f.tangential.norm() ==
          Approx(std::min(mu * (f.normal + 2 * nc), h.peeled && t0 < t_c ? t_c : 1e300))
              .epsilon(1e-9));
  }
}

TEST_CASE("thornton_jkr: with shrink_rescale a peeling contact's closed path returns its T",
          "[thornton][jkr]") {
  // Driven without peeling: overlap 0 -> a1, slide +d, overlap -> a2 < a1, slide -d,
  // overlap -> a1: the contact is back where it was. Eq. 6.19 alone (dT = 8 G* a_t
  // d(delta)) unloads at the shrunk contact's smaller stiffness what it loaded at the
  // larger one, so T ends near T1 (1 - a_t2 / a_t1) and the path gave the driver
  // energy; scaled with a_t as the contact shrinks, T ends near 0 and none is given.
  const Vec<3> nz = Vec<3>::UnitZ();
  const double dt = 1e-9, a1 = 10e-9, a2 = 1.5e-9;
  const int n = 2000;
  auto drive = [&](bool rescale, double d, double& t1, double& work, bool& peeled) {
    const auto p = ThorntonJkr::make(
        {{"friction", mu}, {"surface_energy", 0.2}, {"shrink_rescale", rescale ? 1.0 : 0.0}},
        {glass, glass});
    ThorntonJkr::History<3> h{};
    work = 0, peeled = false;
    double t = 0;
    auto step = [&](double overlap, double slip) {
      const ContactForce<3> f =
          ThorntonJkr::force<3>(p, h, state<3>(nz, overlap, planar<3>(slip / dt, 0), dt));
      // The work the driver does on the contact over this step (trapezoid).
      work += 0.5 * (t + f.tangential[0]) * slip;
      t = f.tangential[0];
      peeled = peeled || h.peeled;
    };
    for (int k = 1; k <= n; ++k) step(a1 * k / n, 0);
    for (int k = 1; k <= n; ++k) step(a1, d / n);
    t1 = t;
    for (int k = 1; k <= n; ++k) step(a1 + (a2 - a1) * k / n, 0);
    for (int k = 1; k <= n; ++k) step(a2, -d / n);
    for (int k = 1; k <= n; ++k) step(a2 + (a1 - a2) * k / n, 0);
    return t;
  };
  double t1 = 0, work = 0;
  bool peeled = false;
  // d such that T1 is well below peeling's Tc at the smaller overlap.
  const double d = 2e-11;
  const double plain = drive(false, d, t1, work, peeled);
  INFO("Eq. 6.19 as written: T1 " << t1 << " N, T at the end " << plain << " N, work " << work);
  REQUIRE(!peeled);
  REQUIRE(t1 > 0);
  CHECK(plain > 0.2 * t1);
  CHECK(work < -0.05 * t1 * d);
  const double scaled = drive(true, d, t1, work, peeled);
  INFO("shrink_rescale: T at the end " << scaled << " N, work " << work);
  REQUIRE(!peeled);
  CHECK(std::abs(scaled) < 0.02 * t1);
  CHECK(work > -0.01 * t1 * d);
}

TEMPLATE_TEST_CASE_SIG(
    "thornton_jkr: a peeling contact sheared out and back along the same path returns its T "
    "and the work it took (Eq. 6.19 by the midpoint rule)",
    "[thornton][jkr]", ((int D), D), 2, 3) {
  // At a fixed overlap, Eq. 6.19 with Eq. 6.20's a_t(T) is an elastic law, T a
  // function of the displacement: out to near Tc and back in equal steps must end
  // at T = 0 having returned all the work. With a_t from the step's start T
  // (explicit Euler) it ends at a T of the order of one step's increment, in the
  // direction of the motion out, and gives the driver work: a cluster of adhesive
  // spheres vibrating at rest gains energy every cycle.
  const double gamma = 0.3, dt = 1e-9, r_eff = radius / 2;
  const auto p = jkr_params(mu, gamma);
  const double e = p.elastic.e_star, g = p.elastic.g_star;
  const double a0 = ThorntonJkr::zero_load_radius(gamma, r_eff, e);
  const double overlap = a0 * a0 / r_eff - std::sqrt(2 * pi * gamma * a0 / e);  // N = 0
  const double nc = 1.5 * pi * gamma * r_eff;
  const double t_c = 4 * std::sqrt(g / e * nc * nc);  // Eq. 6.21 at N = 0
  for (const int n : {50, 400}) {
    ThorntonJkr::History<D> h{};
    const Vec<D> normal = planar<D>(0, -1);
    ThorntonJkr::force<D>(p, h, state<D>(normal, 1.01 * overlap, Vec<D>::Zero(), dt, 1e-8, r_eff));
    ThorntonJkr::force<D>(p, h, state<D>(normal, overlap, Vec<D>::Zero(), dt, 1e-8, r_eff));
    // n steps out to about 0.9 Tc (the stiffness falls by a third on the way).
    const double slip = 0.9 * t_c / (8 * g * a0) / n * 1.1;
    double t = 0, work = 0, t_max = 0;
    auto step = [&](double sign) {
      const ContactForce<D> f = ThorntonJkr::force<D>(
          p, h, state<D>(normal, overlap, planar<D>(sign * slip / dt, 0), dt, 1e-8, r_eff));
      work += 0.5 * (t + f.tangential[0]) * sign * slip;
      t = f.tangential[0];
      t_max = std::max(t_max, t);
      REQUIRE(f.tangential[1] == 0.0);
    };
    for (int k = 0; k < n; ++k) step(1);
    REQUIRE(!h.peeled);
    REQUIRE(t_max > 0.8 * t_c);
    REQUIRE(t_max < t_c);
    for (int k = 0; k < n; ++k) step(-1);
    INFO(n << " steps each way: T_max / Tc " << t_max / t_c << ", T at the end / T_max "
           << t / t_max << ", work / (T_max slip n) " << work / (t_max * slip * n));
    CHECK(std::abs(t) < 1e-9 * t_max);
    CHECK(std::abs(work) < 1e-9 * t_max * slip * n);
  }
}
