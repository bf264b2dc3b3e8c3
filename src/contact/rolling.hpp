// Rolling and twisting resistance, a term any contact model can carry:
// WithRolling<M> is model M with a rolling torque (and, in 3D, a twisting
// torque) added, registered beside M (models.hpp), so a material pair that
// declares `rolling_friction > 0` or `twisting_friction > 0` has its contacts
// in another bucket whose kernel computes the torques, and a scene without
// them runs M's kernel unchanged (docs/features_cost.md).
//
// The relative rolling velocity is w_r = w_i - w_j without its component
// along the normal, Ai et al. 2011, Eq. 11; the torque M acts on i and -M on
// j (against a wall, w_j is the wall's spin).
// Two forms (rolling_model):
//  - "epsd", the elastic-plastic spring-dashpot (type C of Ai, Chen, Rotter
//    and Ooi 2011, Eqs. 12-15): a spring torque M_k, incremented by
//    -k_r w_r dt and carried in the contact's history (turned with the contact
//    as the tangential spring is), capped at M_m = mu_r R* N; below the cap a
//    dashpot M_d = -C_r w_r with C_r = eta_r 2 sqrt(I_r k_r) acts too (eta_r =
//    rolling_damping, 0 by default; at the cap no dashpot, Ai's f = 0). The
//    torque, spring and dashpot together, is at most M_m: Ai's dashpot below
//    the cap is unbounded, and where N rises fast (an impact, a ringing
//    undamped normal law) it would resist rolling by many times M_m.
//    k_r = 2.25 k_n mu_r^2 R*^2 (Wensrich and Katterfeld 2012, the stiffness
//    LIGGGHTS's epsd2 and MercuryDPM use), with k_n the normal law's stiffness
//    at this overlap (the model's normal_stiffness, else the secant N / delta),
//    and I_r = [1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2)]^-1 (Ai Eq. 13).
//  - "constant" (type A of Ai et al.): M = -mu_r R* N w_r / |w_r|. So that it
//    never reverses the relative rolling, its magnitude is at most
//    |w_r| / ((1/I_i + 1/I_j) dt), the torque that by itself stops the relative
//    spin in one step: below that rolling speed it brings w_r to zero rather
//    than through it (the threshold below which it is held at zero, in the
//    form that has no free constant). Being zero at w_r = 0 it cannot hold a
//    sphere at rest against a steady torque (on an incline below its angle
//    of repose it creeps at a speed proportional to dt, as Ai et al. note of
//    type A): "epsd" can.
// Twisting (3D; a 2D scene's spins are about z, normal to every contact
// normal, so nothing twists there) is the same law about the normal, a
// scalar: the relative twist w_t = n . (w_i - w_j), the cap M_t = mu_t R* N
// (mu_t = twisting_friction), with "epsd" a spring T incremented by
// -k_t w_t dt, k_t = 2.25 k_n mu_t^2 R*^2 (the rolling spring's rule, so
// that the spring slips at a twist of N / (2.25 k_n mu_t R*), delta /
// (2.25 mu_t R*) for a linear law, as the rolling one at such a roll), and
// below the cap the dashpot 2 eta_r sqrt(I_t k_t) with I_t = [1/I_i +
// 1/I_j]^-1; with "constant" T = -M_t sign(w_t), never more than stops w_t in
// the step. The torque T n acts on i and -T n on j, about the same axis, so
// the pair's angular momentum is kept.
// The springs' k_n follows the overlap (but for the linear law). They hold
// M_k / sqrt(k_r) and T / sqrt(k_t), so that a change of stiffness leaves
// their energy alone: holding the torque itself (as Ai et al. and LIGGGHTS
// write it), a spring is pumped up to its cap, undamped, by a normal load
// ringing at about twice its frequency (a parametric resonance no normal force
// pays for). Under the linear law the rolling spring holds M_k.
// The EPSD springs add rotational modes. A sphere on a wall held by friction
// rocks about the contact point (Ai's I_r = [1/(I_i + m_i r_i^2) + ...]^-1,
// the inertia the dashpot is tuned to), but a sphere free to slip (no
// friction), and two spheres turning in opposite senses, turn about their own
// centres: omega^2 = k / [1/I_i + 1/I_j]^-1, the faster. As that inertia is
// >= 0.4 m* R*^2 for spheres (R* <= each radius; equality for a sphere on a
// wall), omega_r <= sqrt(k_r-factor / 0.4) mu_r omega_n and omega_t <=
// sqrt(k_r-factor / 0.4) mu_t omega_n, which bound the stability limit
// (2.37 mu times omega_n with the default 2.25).
// N is the normal force kept >= 0; an adhesive law gives its own load and
// stiffness (has_resisting: thornton_jkr's N + 2Nc and 4 E* a / 3, so that a
// contact held together at N = 0 resists rolling and twisting).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "contact/contact_state.hpp"
#include "contact/parameters.hpp"
#include "core/errors.hpp"

namespace granule {

namespace rolling_model {
constexpr int epsd = 0;
constexpr int constant = 1;
}  // namespace rolling_model

// "epsd" or "constant" as the code the parameter table holds; InputError
// naming `context` and the known names otherwise.
double rolling_model_code(const std::string& name, const std::string& context);
// The name of a code the parameter table holds ("epsd", "constant"), for
// every place that shows a pair's parameters to a person or a reader of the output.
const char* rolling_model_name(double code);
// The parameters of the rolling term (rolling and twisting), which every
// model's rolling variant carries.
std::vector<ParamSpec> rolling_parameters();
// Whether a parameter name is one of them.
bool is_rolling_parameter(const std::string& name);

struct RollingParams {
  double friction = 0;  // mu_r
  double twisting = 0;  // mu_t (3D)
  int model = rolling_model::epsd;
  double stiffness = 2.25;  // k_r / (k_n mu_r^2 R*^2), and k_t / (k_n mu_t^2 R*^2)
  double damping = 0;       // eta_r, for both dashpots
};

// The rolling and twisting springs' stiffest mode against the normal law's,
// at most (the header above): max(omega_r, omega_t) / omega_n.
inline double spring_mode_ratio(const RollingParams& r) {
  return std::sqrt(r.stiffness / 0.4) * std::max(r.friction, r.twisting);
}

// Whether model M states its normal stiffness at an overlap
// (`static double normal_stiffness(const Params&, double r_star, double overlap)`).
template <typename M, typename = void>
struct has_normal_stiffness : std::false_type {};

template <typename M>
struct has_normal_stiffness<M, std::void_t<decltype(M::normal_stiffness(
                                   std::declval<const typename M::Params&>(), 0.0, 0.0))>>
    : std::true_type {};

// Whether model M gives the load and stiffness its contacts' rolling and
// twisting resistance take (`M::resisting<D>(params, history, r_star, overlap,
// N)` returning .load and .stiffness: an adhesive law, whose contacts hold
// together at N <= 0).
template <typename M, int D, typename = void>
struct has_resisting : std::false_type {};
template <typename M, int D>
struct has_resisting<M, D,
                     std::void_t<decltype(M::template resisting<D>(
                         std::declval<const typename M::Params&>(),
                         std::declval<const typename M::template History<D>&>(), 0.0, 0.0, 0.0))>>
    : std::true_type {};

// Whether a law's normal stiffness is one constant (the linear law), so that
// the rolling spring's stiffness never changes under it.
template <typename M, typename = void>
struct has_constant_normal_stiffness : std::false_type {};
template <typename M>
struct has_constant_normal_stiffness<M, std::enable_if_t<M::constant_normal_stiffness>>
    : std::true_type {};

// Whether a law gives its normal mode's limit apart from its stability_limit
// (which may count its tangential spring's mode too).
template <class M, class = void>
struct has_normal_stability_limit : std::false_type {};
template <class M>
struct has_normal_stability_limit<
    M, std::void_t<decltype(M::normal_stability_limit(std::declval<const typename M::Params&>(),
                                                      std::declval<const PairScale&>()))>>
    : std::true_type {};

// Whether a law's stiffness grows with the overlap past what its step rule
// assumed, and says how (mode_squared: the Hertzian laws).
template <class M, class = void>
struct has_mode_squared : std::false_type {};
template <class M>
struct has_mode_squared<
    M, std::void_t<decltype(M::mode_squared(std::declval<const typename M::Params&>(),
                                            std::declval<const PairScale&>(), 0.0))>>
    : std::true_type {};

// Whether a law gives its normal mode's omega^2 at an overlap apart from its
// stiffest one (normal_mode_squared).
template <class M, class = void>
struct has_normal_mode_squared : std::false_type {};
template <class M>
struct has_normal_mode_squared<
    M, std::void_t<decltype(M::normal_mode_squared(std::declval<const typename M::Params&>(),
                                                   std::declval<const PairScale&>(), 0.0))>>
    : std::true_type {};

// Whether a model carries the rolling term (the kernels add its torque).
template <typename M, typename = void>
struct has_rolling : std::false_type {};
template <typename M>
struct has_rolling<M, std::enable_if_t<M::rolling>> : std::true_type {};

// 1 / (I + m r^2) of one body from its inverses; 0 for a fixed one (or a wall).
inline double rolling_compliance(double inv_mass, double inv_inertia, double radius) {
  const double d = inv_mass + radius * radius * inv_inertia;
  return d > 0 ? inv_mass * inv_inertia / d : 0.0;
}
// I_r of Ai Eq. 13 from the two compliances; 0 when neither body can move.
inline double rolling_inertia(double compliance_i, double compliance_j) {
  const double s = compliance_i + compliance_j;
  return s > 0 ? 1.0 / s : 0.0;
}

template <typename M, const char* Name>
struct WithRolling {
  using Base = M;
  static constexpr const char* name = Name;
  static constexpr const char* doc = M::doc;
  static constexpr bool adhesive = M::adhesive;
  static constexpr bool rolling = true;
  static constexpr bool uses_effective_mass = ::granule::uses_effective_mass<M>::value;
  static constexpr bool uses_effective_radius = true;  // R* sets the rolling cap

  static std::vector<ParamSpec> parameters() {
    std::vector<ParamSpec> out = M::parameters();
    for (const ParamSpec& p : rolling_parameters()) out.push_back(p);
    return out;
  }

  struct Params {
    typename M::Params base;
    RollingParams roll;
  };

  static Params make(const ParamValues& v, const PairMaterials& m) {
    Params p{M::make(v, m), {}};
    p.roll.friction = v.at("rolling_friction");
    p.roll.twisting = v.at("twisting_friction");
    p.roll.model = static_cast<int>(v.at("rolling_model"));
    p.roll.damping = v.at("rolling_damping");
    // The term without either torque would be the plain law in another bucket,
    // its other parameters (rolling_model, rolling_damping) doing nothing.
    if (!(p.roll.friction > 0) && !(p.roll.twisting > 0))
      throw InputError(
          "rolling_model and rolling_damping act only with rolling_friction > 0 or "
          "twisting_friction > 0");
    // The constant torque has no dashpot: a damping given with it would be echoed in
    // the run header and do nothing.
    if (p.roll.model == rolling_model::constant && p.roll.damping != 0)
      throw InputError(
          fmt::format("rolling_damping = {} acts only with rolling_model = \"epsd\" (the constant "
                      "torque has no dashpot)",
                      p.roll.damping));
    return p;
  }

  // Whether the rolling spring holds M_k / sqrt(k_r) (sqrt(J)) rather than M_k
  // (N m): wherever k_r follows the overlap (rolling_part).
  static constexpr bool rolling_spring_scaled = !has_constant_normal_stiffness<M>::value;

  template <int D>
  struct History {
    typename M::template History<D> base{};
    // The EPSD rolling spring's torque on i, M_k (N m), or M_k / sqrt(k_r)
    // (sqrt(J)) where rolling_spring_scaled.
    Spin<D> rolling = Dim<D>::zero_spin();
    double twisting = 0;  // sqrt(J): the EPSD twisting spring's torque on i along n over sqrt(k_t)
  };
  // The history as builds without the twisting torque wrote it (checkpoints
  // they wrote are read with twisting = 0).
  template <int D>
  struct HistoryWithoutTwisting {
    typename M::template History<D> base{};
    Spin<D> rolling = Dim<D>::zero_spin();
  };
  template <int D>
  static History<D> from_history_without_twisting(const HistoryWithoutTwisting<D>& old) {
    History<D> h;
    h.base = old.base;
    h.rolling = old.rolling;
    return h;
  }

  template <int D>
  static bool touching(const Params& p, const History<D>& h, double overlap) {
    return M::touching(p.base, h.base, overlap);
  }
  static double reach(const Params& p, double r_star) { return M::reach(p.base, r_star); }
  static constexpr bool steps_per_contact_counted = M::steps_per_contact_counted;
  static double rule_time_step(const Params& p, const PairScale& s, double steps_per_contact) {
    return M::rule_time_step(p.base, s, steps_per_contact);
  }
  // The stiffest mode at an overlap, where the law says its own
  // (has_mode_squared): the law's, or the rolling and twisting springs' (up to
  // `ratio` times its normal mode; where the law does not give that apart,
  // its stiffest mode stands in, which can only overstate the springs').
  template <class Base = M, class = std::enable_if_t<has_mode_squared<Base>::value>>
  static double mode_squared(const Params& p, const PairScale& s, double overlap) {
    const double base = Base::mode_squared(p.base, s, overlap);
    if (p.roll.model != rolling_model::epsd) return base;
    const double ratio = spring_mode_ratio(p.roll);
    double normal = base;
    if constexpr (has_normal_mode_squared<Base>::value)
      normal = Base::normal_mode_squared(p.base, s, overlap);
    return std::max(base, ratio * ratio * normal);
  }
  // The law's own limit, and the rolling and twisting springs': omega_r or omega_t
  // up to `ratio` times the normal mode's omega_n, so their limit is the normal
  // one's over ratio (a law whose limit also counts its tangential spring says
  // its normal one apart).
  static double stability_limit(const Params& p, const PairScale& s) {
    const double base = M::stability_limit(p.base, s);
    if (p.roll.model != rolling_model::epsd) return base;
    const double ratio = spring_mode_ratio(p.roll);
    if (!(ratio > 1)) return base;
    double normal = base;
    if constexpr (has_normal_stability_limit<M>::value)
      normal = M::normal_stability_limit(p.base, s);
    return std::min(base, normal / ratio);
  }

  template <int D>
  static ContactForce<D> force(const Params& p, History<D>& h, const ContactState<D>& c) {
    return M::force(p.base, h.base, c);
  }

  // k_n of k_r = 2.25 k_n mu_r^2 R*^2 and k_t = 2.25 k_n mu_t^2 R*^2.
  static double normal_stiffness_of(const Params& p, double r_star, double overlap,
                                    double normal_force) {
    if constexpr (has_normal_stiffness<M>::value)
      return M::normal_stiffness(p.base, r_star, overlap);
    else
      return overlap > 0 && normal_force > 0 ? normal_force / overlap : 0.0;
  }

  // The rolling and twisting torque on i (j feels minus it), after force() of
  // the same step: `normal_force` is its N, `spin_difference` w_i - w_j,
  // `inertia` I_r and `inv_inertia_sum` 1/I_i + 1/I_j (0 for a wall or fixed particle).
  template <int D>
  static Spin<D> rolling_torque(const Params& p, History<D>& h, const ContactState<D>& c,
                                double normal_force, const Spin<D>& spin_difference, double inertia,
                                double inv_inertia_sum) {
    double n_force = std::max(normal_force, 0.0), k_n = 0;
    if constexpr (has_resisting<M, D>::value) {
      const auto resisting =
          M::template resisting<D>(p.base, h.base, c.effective_radius, c.overlap, normal_force);
      n_force = resisting.load;
      k_n = resisting.stiffness;
    } else if (p.roll.model == rolling_model::epsd) {
      k_n = normal_stiffness_of(p, c.effective_radius, c.overlap, n_force);
    }
    // A torque whose coefficient a run set to 0 holds no spring, so that it
    // starts afresh if the coefficient is raised again.
    Spin<D> torque = Dim<D>::zero_spin();
    if (p.roll.friction > 0)
      torque = rolling_part(p.roll, h.rolling, c, n_force, k_n, spin_difference, inertia,
                            inv_inertia_sum);
    else
      h.rolling = Dim<D>::zero_spin();
    if constexpr (D == 3) {
      if (p.roll.twisting > 0)
        torque += c.normal * twisting_part(p.roll, h.twisting, c, n_force, k_n,
                                           c.normal.dot(spin_difference), inv_inertia_sum);
      else
        h.twisting = 0;
    }
    return torque;
  }

 private:
  template <int D>
  static Spin<D> rolling_part(const RollingParams& r, Spin<D>& held, const ContactState<D>& c,
                              double n_force, double k_n, const Spin<D>& spin_difference,
                              double inertia, double inv_inertia_sum) {
    using S = Spin<D>;
    const double cap = r.friction * c.effective_radius * n_force;  // M_m
    S w_r = spin_difference;
    if constexpr (D == 3) w_r -= c.normal * c.normal.dot(spin_difference);  // twisting apart
    if (r.model == rolling_model::constant) {
      const double speed = std::sqrt(Dim<D>::spin_sq(w_r));
      if (!(speed > 0)) return Dim<D>::zero_spin();
      // A hair less than the whole spin, so that round-off in the integration
      // cannot take it through zero (inf when nothing can turn).
      const double stopping = (1 - 1e-12) * speed / (inv_inertia_sum * c.dt);
      return S(w_r * (-std::min(cap, stopping) / speed));
    }
    const double lever = r.friction * c.effective_radius;
    const double k_r = r.stiffness * k_n * lever * lever;
    // Where k_r follows the overlap the spring holds M_k / sqrt(k_r) (as the
    // twisting spring, below): holding M_k, an undamped normal load ringing at
    // twice the rolling mode's frequency pumped the rocking up to the cap.
    // Under the linear law k_r is constant and the spring holds M_k itself.
    S carried = held;
    if constexpr (D == 3) carried = rotate_onto_plane<3>(held, c.normal);
    return spring_slider<rolling_spring_scaled, false>(held, carried, k_r, w_r, cap, r.damping,
                                                       inertia, inv_inertia_sum, c.dt);
  }

  // The twisting torque along n on i, from the relative twist w_t = n . (w_i - w_j):
  // the rolling part's law about the normal (the header), a scalar that needs
  // no turning with the contact.
  static double twisting_part(const RollingParams& r, double& held, const ContactState<3>& c,
                              double n_force, double k_n, double w_t, double inv_inertia_sum) {
    const double cap = r.twisting * c.effective_radius * n_force;  // M_t
    if (r.model == rolling_model::constant) {
      if (!(std::abs(w_t) > 0)) return 0.0;
      const double stopping = (1 - 1e-12) * std::abs(w_t) / (inv_inertia_sum * c.dt);
      return -std::copysign(std::min(cap, stopping), w_t);
    }
    const double lever = r.twisting * c.effective_radius;
    const double k_t = r.stiffness * k_n * lever * lever;
    // I_t = 1 / (1/I_i + 1/I_j), the dashpot's inertia.
    const double inertia = inv_inertia_sum > 0 ? 1.0 / inv_inertia_sum : 0.0;
    return spring_slider<true, true>(held, held, k_t, w_t, cap, r.damping, inertia, inv_inertia_sum,
                                     c.dt);
  }

  // Dim<D> of a spin value: a scalar is a 2D spin (or a twist), a vector a 3D one.
  template <typename S>
  using SpinOf = Dim<std::is_arithmetic_v<S> ? 2 : 3>;

  // One step of an epsd spring-slider and its dashpot, on a rolling spring (a
  // spin vector) or a twisting one (a scalar): `carried` is the spring as
  // held, carried onto this step's tangent plane. Scaled, it holds the torque
  // over sqrt(k), its energy u^2 / 2, so that k changing with the overlap
  // leaves that energy as it was (holding the torque, a normal load ringing at
  // twice the spring's frequency pumped it up to the cap: a parametric
  // resonance no normal force paid for); unloaded (k = 0) it holds nothing.
  // Signed: a twisting spring, compared with the cap by |T| and its sign.
  // Returns the torque on i, at most `cap`: the spring slips there, with no
  // dashpot (Ai's f = 0); below it the dashpot 2 eta sqrt(I k), held at what
  // stops the relative spin w in one step (C dt (1/I_i + 1/I_j) > 1 would
  // more than stop it and, past 2, make it grow step by step: a resting sphere
  // spun up to the cap), as the constant model's torque is.
  template <bool Scaled, bool Signed, typename S>
  static S spring_slider(S& held, const S& carried, double k, const S& w, double cap,
                         double damping, double inertia, double inv_inertia_sum, double dt) {
    double root = 1;
    if constexpr (Scaled) {
      if (!(k > 0)) {
        held = SpinOf<S>::zero_spin();  // a scalar, or a 3D spin
        return held;
      }
      root = std::sqrt(k);
    }
    S spring = carried;
    if constexpr (Scaled) spring *= root;
    spring -= k * dt * w;
    if (beyond<Signed>(spring, cap)) {  // fully mobilised: the spring slips at the cap
      spring = capped<Signed>(spring, cap);
      held = Scaled ? S(spring / root) : spring;
      return spring;
    }
    held = Scaled ? S(spring / root) : spring;
    if (damping == 0) return spring;
    const double c_d = std::min(2 * damping * std::sqrt(inertia * k), 1.0 / (inv_inertia_sum * dt));
    const S total = spring - c_d * w;
    return beyond<Signed>(total, cap) ? capped<Signed>(total, cap) : total;
  }
  // |v| > cap, and v brought to length cap: by |v|^2 for a spin (a 2D one is
  // a scalar), by |v| and its sign for the twisting spring (Signed).
  template <bool Signed, typename S>
  static bool beyond(const S& v, double cap) {
    if constexpr (Signed)
      return std::abs(v) > cap;
    else
      return SpinOf<S>::spin_sq(v) > cap * cap;
  }
  template <bool Signed, typename S>
  static S capped(const S& v, double cap) {
    if constexpr (Signed)
      return std::copysign(cap, v);
    else
      return S(v * (cap / std::sqrt(SpinOf<S>::spin_sq(v))));
  }
};

}  // namespace granule
