// Linear spring-dashpot with a Coulomb-capped tangential spring (Cundall and
// Strack), as LAMMPS' gran/hooke/history and LIGGGHTS' hooke define it, so
// users of those codes can compare (SPEC 3.4; not in the dissertation).
//
// Normal: N = k_n a + c_n da/dt with c_n = 2 zeta sqrt(m* k_n); the damping
// ratio zeta comes from the restitution e, e = exp(-pi zeta / sqrt(1 - zeta^2)).
// Like LAMMPS, the normal force may turn slightly tensile at the end of an
// impact (that is what makes the closed form exact); allow_tension = 0 clamps
// it at zero instead, which raises the restitution a little.
// Tangential: spring k_t = ratio * k_n on the accumulated slip, dashpot
// c_t = ratio_damping * c_n, capped at mu |N|; the spring is shortened when
// sliding so that it stores exactly the capped force.
#pragma once

#include <cmath>
#include <type_traits>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_state.hpp"
#include "contact/parameters.hpp"

namespace granule {

struct LinearSpringDashpot {
  static constexpr const char* name = "linear";
  static constexpr const char* doc =
      "linear spring-dashpot normal force with a Coulomb-capped tangential spring "
      "(Cundall-Strack; LAMMPS gran/hooke/history)";
  static constexpr bool adhesive = false;
  static constexpr bool uses_effective_radius = false;
  static constexpr bool uses_effective_mass = false;  // sqrt(m*) from inv_mass_sum, once a contact

  static std::vector<ParamSpec> parameters() {
    return {
        {"k_normal", "N/m", required, 0, unbounded, false, "normal spring stiffness k_n"},
        {"restitution", "-", required, 0, 1, false, "normal coefficient of restitution e"},
        {"friction", "-", 0.0, 0, unbounded, true, "Coulomb friction coefficient mu"},
        {"tangential_ratio", "-", 2.0 / 7.0, 0, unbounded, true, "k_t / k_n"},
        {"tangential_damping_ratio", "-", 0.5, 0, unbounded, true,
         "c_t / c_n (LAMMPS' default 0.5)"},
        {"allow_tension", "-", 1, 0, 1, true,
         "1: the dashpot may pull at the end of an impact (closed-form restitution); 0: N >= 0",
         true},
    };
  }

  struct Params {
    double k_normal, damping_ratio, friction, k_tangential, tangential_damping_ratio;
    double sqrt_k_normal;
    double inv_k_tangential;  // 1/k_t, 0 when k_t = 0 (the spring then stores nothing)
    bool allow_tension;
  };

  static double damping_ratio_for(double restitution) {
    double l = std::log(restitution);
    return -l / std::sqrt(pi * pi + l * l);
  }

  static Params make(const ParamValues& v, const PairMaterials&) {
    Params p;
    p.k_normal = v.at("k_normal");
    p.sqrt_k_normal = std::sqrt(p.k_normal);
    p.damping_ratio = damping_ratio_for(v.at("restitution"));
    p.friction = v.at("friction");
    p.k_tangential = v.at("tangential_ratio") * p.k_normal;
    p.inv_k_tangential = p.k_tangential > 0 ? 1.0 / p.k_tangential : 0.0;
    p.tangential_damping_ratio = v.at("tangential_damping_ratio");
    p.allow_tension = v.at("allow_tension") != 0;
    return p;
  }

  struct History3 {
    Vec<3> slip = Vec<3>::Zero();  // accumulated tangential spring elongation, m
    double sqrt_mass = -1;         // sqrt(m*) of this contact, kg^1/2; < 0: not computed yet
  };
  // 2D: the spring's elongation along t = (-n_y, n_x), which turns with the
  // contact, so carrying it onto the new tangent line costs nothing (the
  // vector form rotates it there keeping its length and side: the same).
  struct History2 {
    double slip = 0;  // m, along t
    double sqrt_mass = -1;
  };
  template <int D>
  using History = std::conditional_t<D == 2, History2, History3>;

  template <typename H>
  static bool touching(const Params&, const H&, double overlap) {
    return overlap > 0;
  }

  static double contact_duration(const Params& p, double effective_mass) {
    double omega0 = std::sqrt(p.k_normal / effective_mass);
    return pi / (omega0 * std::sqrt(1 - p.damping_ratio * p.damping_ratio));
  }
  // What rule_time_step's n counts (the run header says it): steps per contact.
  static constexpr bool steps_per_contact_counted = true;
  static double rule_time_step(const Params& p, const PairScale& s, double steps_per_contact) {
    return contact_duration(p, s.effective_mass) / steps_per_contact;
  }
  // For the rolling stiffness (rolling.hpp), which is then constant: its
  // spring holds the torque itself.
  static double normal_stiffness(const Params& p, double, double) { return p.k_normal; }
  static constexpr bool constant_normal_stiffness = true;
  // 2 / omega of the normal spring alone (the rolling term scales this one).
  static double normal_stability_limit(const Params& p, const PairScale& s) {
    return 2.0 / std::sqrt(p.k_normal / s.effective_mass);
  }
  // 2 / omega of the stiffer of the contact's modes: the normal spring's, and
  // with friction the tangential spring's, omega_t^2 = 3.5 k_t / m*
  // (tangential_mass_factor). The default k_t = 2/7 k_n makes the two equal.
  // And the dashpots': an explicit dashpot c stops the relative motion of mass m
  // in one step at c dt / m = 1 and reverses it beyond (an impact at e -> 0 then
  // rebounds faster than it came: t_c grows as 1/sqrt(1 - zeta^2), so the rule's
  // t_c / n does too). The engine accepts half of this limit, so 2 m / c here:
  // 1 / (zeta omega_n) for c_n = 2 zeta sqrt(k_n m*), and with friction
  // 1 / (3.5 r_t zeta omega_n) for c_t = r_t c_n on the tangential mode's mass
  // m* / 3.5. (Held to c dt / m <= 1 with omega dt <= 1, leap-frog's damped
  // oscillator, omega^2 dt^2 + 4 zeta omega dt < 4, is stable too.)
  static double stability_limit(const Params& p, const PairScale& s) {
    const double k =
        p.friction > 0 ? std::max(p.k_normal, tangential_mass_factor * p.k_tangential) : p.k_normal;
    double limit = 2.0 / std::sqrt(k / s.effective_mass);
    const double zeta_omega = p.damping_ratio * std::sqrt(p.k_normal / s.effective_mass);
    if (zeta_omega > 0) {
      limit = std::min(limit, 1.0 / zeta_omega);
      if (p.friction > 0 && p.tangential_damping_ratio > 0)
        limit = std::min(limit,
                         1.0 / (tangential_mass_factor * p.tangential_damping_ratio * zeta_omega));
    }
    return limit;
  }

  template <int D>
  static ContactForce<D> force(const Params& p, History<D>& h, const ContactState<D>& c) {
    ContactForce<D> out;
    // sqrt(m*) depends only on the pair: one square root per contact, not per step
    // (a change of k_n or e during a run still applies at once).
    if (h.sqrt_mass < 0) h.sqrt_mass = 1.0 / std::sqrt(c.inv_mass_sum);
    const double c_n = 2.0 * p.damping_ratio * p.sqrt_k_normal * h.sqrt_mass;
    double normal = p.k_normal * c.overlap + c_n * c.normal_velocity;
    if (!p.allow_tension && normal < 0) normal = 0;
    out.normal = normal;
    if (p.friction == 0 && p.k_tangential == 0) return out;

    const double c_t = p.tangential_damping_ratio * c_n;
    if constexpr (D == 2) {
      const Vec<2> t_axis(-c.normal.y(), c.normal.x());
      const double v_t = c.tangential_velocity.dot(t_axis);
      double slip = h.slip + v_t * c.dt;
      double t = p.k_tangential * slip + c_t * v_t;
      const double limit = p.friction * std::abs(normal);
      if (std::abs(t) > limit) {
        t = t > 0 ? limit : -limit;
        slip = p.k_tangential > 0 ? (t - c_t * v_t) / p.k_tangential : 0.0;
      }
      h.slip = slip;
      out.tangential = t * t_axis;
      return out;
    } else {
      Vec<D> slip = rotate_onto_plane<D>(h.slip, c.normal) + c.tangential_velocity * c.dt;
      Vec<D> t = p.k_tangential * slip + c_t * c.tangential_velocity;
      const double limit = p.friction * std::abs(normal);
      const double t_sq = t.squaredNorm();
      if (t_sq > limit * limit) {
        t *= limit / std::sqrt(t_sq);
        // Keep the spring consistent with the capped force (LAMMPS does the same);
        // 1/k_t is 0 when k_t is: the spring then stores nothing.
        slip = (t - c_t * c.tangential_velocity) * p.inv_k_tangential;
      }
      h.slip = slip;
      out.tangential = t;
      return out;
    }
  }

  // force() for a batch of 3D contacts (contact_batch.hpp), the same formulas
  // lane by lane, written without branches: the sliding cap and the tension
  // clamp as selects, the spring turned onto the new tangent plane by
  // rotate_lanes_onto_plane().
  struct BatchHistory3 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double sx[lanes], sy[lanes], sz[lanes];  // slip, m
    alignas(64) double sqrt_mass[lanes];
    void load(int l, const History3& h) {
      sx[l] = h.slip.x(), sy[l] = h.slip.y(), sz[l] = h.slip.z();
      sqrt_mass[l] = h.sqrt_mass;
    }
    void store(int l, History3& h) const {
      h.slip = Vec<3>(sx[l], sy[l], sz[l]);
      h.sqrt_mass = sqrt_mass[l];
    }
    void pad(int l) { sx[l] = sy[l] = sz[l] = 0, sqrt_mass[l] = 1; }
    // History3 is these four doubles in this order: the engine may move a
    // contact's history to and from its lane as one row (pair_batch.hpp).
    static constexpr bool four_doubles = true;
    double* column(int q) { return q == 0 ? sx : q == 1 ? sy : q == 2 ? sz : sqrt_mass; }
  };
  static_assert(sizeof(History3) == 4 * sizeof(double), "History3 as one row of four doubles");

  // Each lane's parameters: one law's values for every lane (Uniform), or
  // arrays with a value per lane (a batch that mixes material pairs).
  template <bool Uniform>
  struct LaneParams;

  static void force_batch(const Params* const lane[], BatchHistory3& h, ContactBatch<3>& c);
  // sqrt(m*) is taken once per contact, on its first step (contact_batch.hpp).
  template <typename H>
  static bool batch_needs_mass(const H& h) {
    return h.sqrt_mass < 0;
  }

  // 2D: force() along t lane by lane, the same formulas in the same order.
  struct BatchHistory2 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double slip[lanes];  // m, along t
    alignas(64) double sqrt_mass[lanes];
    void load(int l, const History2& h) { slip[l] = h.slip, sqrt_mass[l] = h.sqrt_mass; }
    void store(int l, History2& h) const { h.slip = slip[l], h.sqrt_mass = sqrt_mass[l]; }
    void pad(int l) { slip[l] = 0, sqrt_mass[l] = 1; }
  };
  static void force_batch(const Params* const lane[], BatchHistory2& h, ContactBatch<2>& c);
  template <typename P>
  static void force_lanes(P q, BatchHistory2& h, ContactBatch<2>& c) {
    const double dt = c.dt;
    for (int l = 0; l < batch_lanes; ++l) {
      const double first_sm = 1.0 / std::sqrt(c.inv_mass_sum[l]);
      const double sm = h.sqrt_mass[l] < 0 ? first_sm : h.sqrt_mass[l];
      h.sqrt_mass[l] = sm;
      const double c_n = q.damping(l) * sm;
      const double raw = q.kn(l) * c.overlap[l] + c_n * c.normal_velocity[l];
      const double normal = q.clamp(l) != 0 && raw < 0 ? 0.0 : raw;
      c.normal_force[l] = normal;
      const double c_t = q.ratio_t(l) * c_n;
      const double v_t = c.tangential_velocity[l];
      const double slip = h.slip[l] + v_t * dt;
      const double kt = q.kt(l);
      const double t = kt * slip + c_t * v_t;
      const double limit = q.mu(l) * std::abs(normal);
      const bool sliding = std::abs(t) > limit;
      const double capped = t > 0 ? limit : -limit;
      const double capped_slip = kt > 0 ? (capped - c_t * v_t) / kt : 0.0;
      const bool on = q.tangential(l) != 0;
      h.slip[l] = !on ? h.slip[l] : sliding ? capped_slip : slip;
      c.tangential_force[l] = !on ? 0.0 : sliding ? capped : t;
    }
  }

  template <typename P>
  static void force_lanes(P q, BatchHistory3& h, ContactBatch<3>& c) {  // q by value: no alias
    constexpr int L = batch_lanes;
    const double dt = c.dt;
    alignas(64) double c_n[L], rx[L], ry[L], rz[L];  // rx...: the spring on the new plane
    // Every value computed in every lane and then chosen: a division or root
    // under a condition would keep the loop from vectorising.
    for (int l = 0; l < L; ++l) {
      const double first_sm = 1.0 / std::sqrt(c.inv_mass_sum[l]);  // a new contact's sqrt(m*)
      const double sm = h.sqrt_mass[l] < 0 ? first_sm : h.sqrt_mass[l];
      h.sqrt_mass[l] = sm;
      c_n[l] = q.damping(l) * sm;
      const double normal = q.kn(l) * c.overlap[l] + c_n[l] * c.normal_velocity[l];
      const double clamped = normal < 0 ? 0.0 : normal;
      c.normal_force[l] = q.clamp(l) != 0 ? clamped : normal;
    }
    // Two loops: in one, GCC 12 does not vectorise them.
    rotate_lanes_onto_plane(c, h.sx, h.sy, h.sz, rx, ry, rz);
    for (int l = 0; l < L; ++l) {
      const double c_t = q.ratio_t(l) * c_n[l];
      const double vx = c.vtx[l], vy = c.vty[l], vz = c.vtz[l];
      const double sx = rx[l] + vx * dt, sy = ry[l] + vy * dt, sz = rz[l] + vz * dt;
      const double kt = q.kt(l);
      double tx = kt * sx + c_t * vx, ty = kt * sy + c_t * vy, tz = kt * sz + c_t * vz;
      const double limit = q.mu(l) * std::abs(c.normal_force[l]);
      const double t_sq = tx * tx + ty * ty + tz * tz;
      const bool sliding = t_sq > limit * limit;
      const double scale = limit / std::sqrt(t_sq);  // used only when sliding (then t_sq > 0)
      tx = sliding ? tx * scale : tx;
      ty = sliding ? ty * scale : ty;
      tz = sliding ? tz * scale : tz;
      // Keep the spring consistent with the capped force, as force() does;
      // with no tangential law it keeps its old elongation and gives no force.
      const double inv_kt = q.inv_kt(l);
      const double new_sx = sliding ? (tx - c_t * vx) * inv_kt : sx;
      const double new_sy = sliding ? (ty - c_t * vy) * inv_kt : sy;
      const double new_sz = sliding ? (tz - c_t * vz) * inv_kt : sz;
      const bool on = q.tangential(l) != 0;
      h.sx[l] = on ? new_sx : h.sx[l];
      h.sy[l] = on ? new_sy : h.sy[l];
      h.sz[l] = on ? new_sz : h.sz[l];
      c.ftx[l] = on ? tx : 0.0, c.fty[l] = on ? ty : 0.0, c.ftz[l] = on ? tz : 0.0;
    }
  }
};

// One law for all lanes: its values, which the lane loops keep in registers.
template <>
struct LinearSpringDashpot::LaneParams<true> {
  double kn_, damping_, ratio_t_, mu_, kt_, inv_kt_;
  double clamp_, tangential_;  // 1 or 0, as in the arrays below
  explicit LaneParams(const Params* const lane[]) {
    const Params& p = *lane[0];
    kn_ = p.k_normal, damping_ = 2.0 * p.damping_ratio * p.sqrt_k_normal;
    ratio_t_ = p.tangential_damping_ratio, mu_ = p.friction;
    kt_ = p.k_tangential, inv_kt_ = p.inv_k_tangential;
    clamp_ = p.allow_tension ? 0.0 : 1.0;
    tangential_ = p.friction == 0 && p.k_tangential == 0 ? 0.0 : 1.0;
  }
  double kn(int) const { return kn_; }
  double damping(int) const { return damping_; }
  double ratio_t(int) const { return ratio_t_; }
  double mu(int) const { return mu_; }
  double kt(int) const { return kt_; }
  double inv_kt(int) const { return inv_kt_; }
  double clamp(int) const { return clamp_; }
  double tangential(int) const { return tangential_; }
};

// Lanes under different laws: each value as an array over the lanes.
template <>
struct LinearSpringDashpot::LaneParams<false> {
  static constexpr int L = batch_lanes;
  alignas(64) double kn_[L], damping_[L], ratio_t_[L], mu_[L], kt_[L], inv_kt_[L];
  alignas(64) double clamp_[L], tangential_[L];  // 1 or 0 (double: the loops vectorise)
  explicit LaneParams(const Params* const lane[]) {
    for (int l = 0; l < L; ++l) {
      const Params& p = *lane[l];
      kn_[l] = p.k_normal, damping_[l] = 2.0 * p.damping_ratio * p.sqrt_k_normal;
      ratio_t_[l] = p.tangential_damping_ratio, mu_[l] = p.friction;
      kt_[l] = p.k_tangential, inv_kt_[l] = p.inv_k_tangential;
      clamp_[l] = p.allow_tension ? 0.0 : 1.0;
      tangential_[l] = p.friction == 0 && p.k_tangential == 0 ? 0.0 : 1.0;
    }
  }
  double kn(int l) const { return kn_[l]; }
  double damping(int l) const { return damping_[l]; }
  double ratio_t(int l) const { return ratio_t_[l]; }
  double mu(int l) const { return mu_[l]; }
  double kt(int l) const { return kt_[l]; }
  double inv_kt(int l) const { return inv_kt_[l]; }
  double clamp(int l) const { return clamp_[l]; }
  double tangential(int l) const { return tangential_[l]; }
};

inline void LinearSpringDashpot::force_batch(const Params* const lane[], BatchHistory3& h,
                                             ContactBatch<3>& c) {
  with_lane_params<LinearSpringDashpot>(lane, [&](const auto& q) { force_lanes(q, h, c); });
}

inline void LinearSpringDashpot::force_batch(const Params* const lane[], BatchHistory2& h,
                                             ContactBatch<2>& c) {
  with_lane_params<LinearSpringDashpot>(lane, [&](const auto& q) { force_lanes(q, h, c); });
}

}  // namespace granule
