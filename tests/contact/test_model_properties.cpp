// One property suite over every registered contact model (the ContactModels
// tuple of contact/models.hpp): a model added to the registry is tested here
// without a new test file, once its required parameters are in
// suite_parameters() (model_properties.hpp). Properties of the engine
// (Newton's third law, angular momentum, histories across list rebuilds, zero
// force once apart, energy of an elastic impact) run two particles through
// Simulation; properties of the law (rotation invariance, the friction cap)
// drive M::force directly along a contact path that loads, unloads, separates,
// turns and slides back and forth.
#include <catch2/catch.hpp>
#include <cmath>

#include "model_properties.hpp"

using namespace granule;
using namespace granule::test;

namespace {

// What caps |T| of model M. Coulomb's mu |N| for a law without adhesion
// (|N|: the linear law's dashpot may pull at the end of an impact); an
// adhesive model states its own cap below.
template <typename M>
struct FrictionCap {
  static_assert(!M::adhesive,
                "an adhesive model's friction cap is its own: add a FrictionCap for it");
  template <int D>
  static double of(const typename M::Params&, const typename M::template History<D>&,
                   const ContactState<D>&, const ContactForce<D>& f) {
    return suite_friction * std::abs(f.normal);
  }
};

// thornton_jkr: while peeling (Eqs. 6.19-6.21) T grows below Tc = 4 sqrt(G*/E* Nc (N + Nc))
// of the current N; once peeled, Mindlin-Deresiewicz with N + 2Nc is capped by the sliding
// force of Eq. 6.23 (N < -0.3 Nc) or Eq. 6.25, mu (N + 2Nc).
template <>
struct FrictionCap<ThorntonJkr> {
  template <int D>
  static double of(const ThorntonJkr::Params& p, const ThorntonJkr::History<D>& h,
                   const ContactState<D>& c, const ContactForce<D>& f) {
    const double nc = ThorntonJkr::pull_off_force(p.surface_energy, c.effective_radius);
    const double slide = ThorntonJkr::sliding_force(p.elastic.friction, f.normal, nc);
    if (h.peeled) return slide;
    const double e = p.elastic.e_star, g = p.elastic.g_star;
    return std::max(slide, 4 * std::sqrt(std::max(0.0, g / e * nc * (f.normal + nc))));
  }
};

// A rolling variant (rolling.hpp) caps T as its model does.
template <typename B, const char* Name>
struct FrictionCap<WithRolling<B, Name>> {
  template <int D>
  static double of(const typename WithRolling<B, Name>::Params& p,
                   const typename WithRolling<B, Name>::template History<D>& h,
                   const ContactState<D>& c, const ContactForce<D>& f) {
    return FrictionCap<B>::template of<D>(p.base, h.base, c, f);
  }
};

template <int D>
Eigen::Matrix<double, D, D> some_rotation() {
  if constexpr (D == 2)
    return Eigen::Rotation2Dd(2.1).toRotationMatrix();
  else
    return Eigen::AngleAxisd(2.1, Eigen::Vector3d(-0.2, 0.9, 0.4).normalized()).toRotationMatrix();
}

// The pair's total angular momentum about the origin, sum m x * v + I w with
// I = 2/5 m r^2 (in 2D its z component).
template <int D>
Eigen::Vector3d angular_momentum(const SimulationBase& sim) {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (std::int64_t id : sim.particle_ids()) {
    const double m = sim.mass(id);
    l += m * as_vec(sim.position(id)).cross(as_vec(sim.velocity(id))) +
         sphere_inertia(m, sim.radius(id)) * as_vec(sim.spin(id));
  }
  return l;
}

template <int D>
double angular_momentum_scale(const SimulationBase& sim) {
  double s = 0;
  for (std::int64_t id : sim.particle_ids()) {
    const double m = sim.mass(id);
    s += m * as_vec(sim.position(id)).norm() * as_vec(sim.velocity(id)).norm() +
         sphere_inertia(m, sim.radius(id)) * as_vec(sim.spin(id)).norm();
  }
  return s;
}

// Runs the pair until its contact has come and gone (or `most` steps), calling
// each(step) after every step.
template <int D, typename F>
std::int64_t run_through_contact(EnginePair<D>& pair, F&& each, std::int64_t most = 200000) {
  bool seen = false;
  for (std::int64_t k = 0; k < most; ++k) {
    pair.sim->advance(1);
    each(k);
    const bool in_contact = !pair.sim->contacts().empty();
    if (in_contact) seen = true;
    if (seen && !in_contact) return k + 1;
  }
  FAIL("the contact did not end within " << most << " steps");
  return most;
}

}  // namespace

TEMPLATE_LIST_TEST_CASE("model properties: the suite knows every registered model",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  INFO("model " << M::name);
  const ParamValues given = given_parameters<M>(false);
  const ParamValues values = resolved_parameters<M>(false);
  // Only required parameters (and those the table names) are given; the rest are defaults.
  for (const auto& p : M::parameters())
    if (!given.count(p.name)) CHECK(values.at(p.name) == p.default_value);
  CHECK(values.at("friction") == suite_friction);
}

TEMPLATE_LIST_TEST_CASE("model properties: Newton's third law, lever arms and angular momentum",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  auto check = [](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D");
    EnginePair<D> pair(oblique_impact<D>(M::name, given_parameters<M>(false, D)));
    SimulationBase& sim = *pair.sim;
    const double dt = sim.time_step();
    const Eigen::Vector3d l0 = angular_momentum<D>(sim);
    const double l_scale = angular_momentum_scale<D>(sim);
    double worst_newton = 0, worst_record = 0, worst_lever = 0, worst_l = 0, largest = 0;
    double largest_torque = 0, largest_rolling = 0;
    int contact_steps = 0;
    Eigen::Vector3d spin_a = as_vec(sim.spin(pair.a)), spin_b = as_vec(sim.spin(pair.b));
    run_through_contact(pair, [&](std::int64_t) {
      const Eigen::Vector3d fa = as_vec(sim.force(pair.a)), fb = as_vec(sim.force(pair.b));
      const Eigen::Vector3d wa = as_vec(sim.spin(pair.a)), wb = as_vec(sim.spin(pair.b));
      worst_newton = std::max(worst_newton, (fa + fb).norm());
      largest = std::max(largest, fa.norm());
      worst_l = std::max(worst_l, (angular_momentum<D>(sim) - l0).norm());
      const auto contacts = sim.contacts();
      if (!contacts.empty()) {
        ++contact_steps;
        const ContactRecord& c = contacts[0];
        const Eigen::Vector3d n = as_vec(c.normal), t = as_vec(c.tangential_force);
        const Eigen::Vector3d on_a = c.normal_force * n + t;  // the record's force on its a
        const Eigen::Vector3d f_rec_a = c.id_a == pair.a ? fa : fb;
        worst_record = std::max(worst_record, (on_a - f_rec_a).norm());
        // Torques from the spin change of this step's kick, w += tau dt / I, against the
        // levers -(r_i - a/2) n on i (which feels T) and +(r_j - a/2) n on j (which feels
        // -T): both -(r - a/2) n x T.
        // A rolling term (rolling.hpp) adds M on one and -M on the other: then the
        // two residuals must cancel, and M must have acted.
        Eigen::Vector3d residual_sum = Eigen::Vector3d::Zero();
        for (std::int64_t id : {c.id_a, c.id_b}) {
          const Eigen::Vector3d dw = id == pair.a ? wa - spin_a : wb - spin_b;
          const Eigen::Vector3d torque = dw * sphere_inertia(sim.mass(id), sim.radius(id)) / dt;
          const Eigen::Vector3d expected = -(sim.radius(id) - 0.5 * c.overlap) * n.cross(t);
          const Eigen::Vector3d residual = torque - expected;
          residual_sum += residual;
          if (has_rolling<M>::value)
            largest_rolling = std::max(largest_rolling, residual.norm());
          else
            worst_lever = std::max(worst_lever, residual.norm());
          largest_torque = std::max(largest_torque, expected.norm());
        }
        if (has_rolling<M>::value) worst_lever = std::max(worst_lever, residual_sum.norm());
      }
      spin_a = wa, spin_b = wb;
    });
    REQUIRE(contact_steps > 10);
    REQUIRE(largest > 0);
    REQUIRE(largest_torque > 0);  // friction acted: the lever check saw torques
    if (has_rolling<M>::value) CHECK(largest_rolling > 1e-3 * largest_torque);
    CHECK(worst_newton == 0.0);  // j receives exactly -F
    CHECK(worst_record <= 1e-12 * largest);
    CHECK(worst_lever <= 1e-9 * largest_torque);
    INFO("angular momentum drift " << worst_l << " of scale " << l_scale);
    CHECK(worst_l <= 1e-12 * l_scale);
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

// At mu = 0 a law may still turn the particles (thornton_jkr's peeling,
// Eqs. 6.18-6.21, resists sliding by adhesion alone; a rolling term): the
// engine must then integrate the spins, or the torques are lost.
TEMPLATE_LIST_TEST_CASE("model properties: angular momentum kept at friction 0",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  auto check = [](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D, friction 0");
    ParamValues given = given_parameters<M>(false, D);
    given["friction"] = 0;
    EnginePair<D> pair(oblique_impact<D>(M::name, given));
    SimulationBase& sim = *pair.sim;
    const Eigen::Vector3d l0 = angular_momentum<D>(sim);
    const double l_scale = angular_momentum_scale<D>(sim);
    double worst_l = 0;
    run_through_contact(pair, [&](std::int64_t) {
      worst_l = std::max(worst_l, (angular_momentum<D>(sim) - l0).norm());
    });
    INFO("angular momentum drift " << worst_l << " of scale " << l_scale);
    CHECK(worst_l <= 1e-12 * l_scale);
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

TEMPLATE_LIST_TEST_CASE("model properties: no force once apart (adhesive: beyond the reach)",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  const auto p = suite_params<M>(false);
  // The law: after a loaded contact history, the pair no longer touches at a gap
  // (an adhesive model: beyond its reach -alpha_f), and an adhesive law gives no force there.
  {
    typename M::template History<3> h;
    for (int k = 0; k < 3000; ++k)
      engine_like_step<M, 3>(p, h, path_state<3>(k, Eigen::Matrix3d::Identity()));
    auto c = path_state<3>(3000, Eigen::Matrix3d::Identity());
    double reach = 0;
    if constexpr (M::adhesive) reach = M::reach(p, c.effective_radius);
    INFO("model " << M::name << ", reach " << reach << " m");
    CHECK(M::adhesive == (reach > 0));
    for (double gap : {1e-12, 1e-9, 1e-7}) {
      c.overlap = -(reach * (1 + 1e-9) + gap);
      auto loaded = h;
      CHECK(!M::touching(p, loaded, c.overlap));
      if constexpr (M::adhesive) {
        const auto f = M::template force<3>(p, loaded, c);
        CHECK(f.normal == 0.0);
        CHECK(f.tangential.norm() == 0.0);
      }
    }
  }
  // The engine: at every step whose gap (before the step's forces) exceeds the
  // reach, both particles feel exactly nothing.
  auto check = [&p](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D");
    EnginePair<D> pair(oblique_impact<D>(M::name, given_parameters<M>(false, D)));
    SimulationBase& sim = *pair.sim;
    const double ra = sim.radius(pair.a), rb = sim.radius(pair.b);
    double reach = 0;
    if constexpr (M::adhesive) reach = M::reach(p, ra * rb / (ra + rb));
    auto gap_now = [&] {
      return (as_vec(sim.position(pair.a)) - as_vec(sim.position(pair.b))).norm() - ra - rb;
    };
    int apart_after_contact = 0, pushed = 0;
    bool touched = false;
    double gap = gap_now();
    run_through_contact(pair, [&](std::int64_t) {
      const double f = as_vec(sim.force(pair.a)).norm() + as_vec(sim.force(pair.b)).norm();
      if (gap > reach) {
        CHECK(f == 0.0);
        if (touched) ++apart_after_contact;
      }
      if (f > 0) touched = true, ++pushed;
      gap = gap_now();
    });
    // The contact ends when the gap passes the reach: run on a little beyond it.
    for (int k = 0; k < 200; ++k) {
      sim.advance(1);
      const double f = as_vec(sim.force(pair.a)).norm() + as_vec(sim.force(pair.b)).norm();
      if (gap > reach) {
        CHECK(f == 0.0);
        ++apart_after_contact;
      }
      gap = gap_now();
    }
    CHECK(pushed > 10);
    CHECK(apart_after_contact > 100);  // the separated pair was seen (and felt nothing)
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

TEMPLATE_LIST_TEST_CASE("model properties: turning the whole contact turns the force with it",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  const auto p = suite_params<M>(false);
  auto check = [&p](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D");
    using R = Eigen::Matrix<double, D, D>;
    const R rotation = some_rotation<D>();
    typename M::template History<D> h, h_turned;
    double worst_normal = 0, worst_tangential = 0, largest_normal = 0, largest_tangential = 0;
    for (int k = 0; k < path_steps; ++k) {
      const auto f = engine_like_step<M, D>(p, h, path_state<D>(k, R::Identity()));
      const auto g = engine_like_step<M, D>(p, h_turned, path_state<D>(k, rotation));
      worst_normal = std::max(worst_normal, std::abs(g.normal - f.normal));
      worst_tangential =
          std::max(worst_tangential, (g.tangential - rotation * f.tangential).norm());
      largest_normal = std::max(largest_normal, std::abs(f.normal));
      largest_tangential = std::max(largest_tangential, f.tangential.norm());
    }
    REQUIRE(largest_normal > 0);
    REQUIRE(largest_tangential > 0);
    INFO("normal " << worst_normal << " of " << largest_normal << ", tangential "
                   << worst_tangential << " of " << largest_tangential);
    CHECK(worst_normal <= 1e-12 * largest_normal);
    // Thornton's branch choices (theta = 1 while |dT| < mu dN, Eq. 6.7; Masing's
    // reversals) compare quantities the rotation changes at round-off, so a step may
    // fall on the other side of a threshold: ~1e-10 of the force (measured 5e-10).
    CHECK(worst_tangential <= 1e-8 * largest_tangential);
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});

  // Through the engine, in 3D: the impact turned as a whole rebounds turned.
  const auto plain = oblique_impact<3>(M::name, given_parameters<M>(false));
  PairSetup turned = plain;
  const Eigen::Matrix3d rotation = some_rotation<3>();
  for (Triple* v : {&turned.position_a, &turned.position_b, &turned.velocity_a, &turned.velocity_b,
                    &turned.spin_a, &turned.spin_b})
    *v = as_triple(rotation * as_vec(*v));
  EnginePair<3> one(plain), two(turned);
  const std::int64_t steps = run_through_contact(one, [](std::int64_t) {});
  two.sim->advance(steps);
  INFO("model " << M::name << ", engine, 3D");
  for (std::int64_t id : {one.a, one.b}) {
    const Eigen::Vector3d v = as_vec(one.sim->velocity(id)), w = as_vec(one.sim->spin(id));
    CHECK((as_vec(two.sim->velocity(id)) - rotation * v).norm() <= 1e-9 * v.norm());
    CHECK((as_vec(two.sim->spin(id)) - rotation * w).norm() <= 1e-9 * w.norm());
  }
}

TEMPLATE_LIST_TEST_CASE("model properties: the tangential force never exceeds its cap",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  const auto p = suite_params<M>(false);
  auto check = [&p](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D");
    using R = Eigen::Matrix<double, D, D>;
    typename M::template History<D> h;
    double worst = 0, closest = 0;
    int sliding_steps = 0;
    for (int k = 0; k < path_steps; ++k) {
      const auto c = path_state<D>(k, R::Identity());
      const auto f = engine_like_step<M, D>(p, h, c);
      const double t = f.tangential.norm();
      if (t == 0) continue;
      const double cap = FrictionCap<M>::template of<D>(p, h, c, f);
      worst = std::max(worst, t / cap);
      if (t >= (1 - 1e-6) * cap) ++sliding_steps;
      closest = std::max(closest, t / cap);
    }
    INFO("largest |T| / cap " << worst << ", steps at the cap " << sliding_steps);
    CHECK(worst <= 1 + 1e-12);
    CHECK(sliding_steps > 100);  // the path slides: the cap was reached, not just respected
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

TEMPLATE_LIST_TEST_CASE("model properties: an elastic head-on impact returns the same speed",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  // Leap-frog conserves the energy of an elastic impact up to an error that falls
  // with (omega dt)^2 or faster (it depends on where the steps fall at first touch
  // and release); with n steps per contact omega dt ~ pi / n, and the rebound speed
  // must come back within (pi / n)^2 (measured: 1e-4 at n = 40 for the linear laws,
  // 1e-6 for the Hertzian ones, falling to 6e-8 and 5e-9 at n = 640).
  auto rebound_error = [](auto dim, double n) {
    constexpr int D = decltype(dim)::value;
    PairSetup s;
    s.model = M::name;
    s.given = given_parameters<M>(true, D);
    s.steps_per_contact = n;
    const double gap = 1e-3 * s.radius_b;
    s.position_a = {-(s.radius_a + s.radius_b + gap), 0, 0};
    s.velocity_a = {0.05, 0, 0};
    s.velocity_b = {-0.05, 0, 0};
    EnginePair<D> pair(s);
    run_through_contact(pair, [](std::int64_t) {});
    const double before = 0.1;
    const double after =
        as_vec(pair.sim->velocity(pair.b)).x() - as_vec(pair.sim->velocity(pair.a)).x();
    return std::abs(after / before - 1);
  };
  for (double n : {40.0, 160.0, 640.0}) {
    const double e2 = rebound_error(std::integral_constant<int, 2>{}, n);
    const double e3 = rebound_error(std::integral_constant<int, 3>{}, n);
    INFO("model " << M::name << ", n = " << n << ": |e - 1| = " << e2 << " (2D), " << e3
                  << " (3D)");
    CHECK(e2 <= (pi / n) * (pi / n));
    CHECK(e3 <= (pi / n) * (pi / n));
  }
}

TEMPLATE_LIST_TEST_CASE("model properties: a contact continued across list rebuilds is unchanged",
                        "[models][properties]", ContactModels) {
  using M = TestType;
  auto check = [](auto dim) {
    constexpr int D = decltype(dim)::value;
    INFO("model " << M::name << ", " << D << "D");
    const auto setup = oblique_impact<D>(M::name, given_parameters<M>(false, D));
    EnginePair<D> plain(setup), churned(setup);
    std::int64_t differing = 0, rebuilt_in_contact = 0;
    bool history_used = false;
    run_through_contact(plain, [&](std::int64_t) {
      // A forced rebuild before every step of the contact: re-sorting the particles
      // (which swaps their storage order) and building the lists anew.
      const bool in_contact = !churned.sim->contacts().empty();
      const auto before = churned.sim->stats().list_rebuilds;
      if (in_contact) churned.sim->sort_particles();
      churned.sim->advance(1);
      if (in_contact && churned.sim->stats().list_rebuilds > before) ++rebuilt_in_contact;
      for (std::int64_t id : {plain.a, plain.b}) {
        const Triple f = plain.sim->force(id), g = churned.sim->force(id);
        const Triple w = plain.sim->spin(id), u = churned.sim->spin(id);
        for (int k = 0; k < 3; ++k) differing += (f[k] != g[k]) + (w[k] != u[k]);
      }
      for (const auto& c : plain.sim->contacts())
        history_used |= as_vec(c.tangential_force).norm() > 0;
    });
    CHECK(rebuilt_in_contact > 10);
    CHECK(history_used);  // the contact carried a tangential history across the rebuilds
    CHECK(differing == 0);
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}
