// Rolling resistance, a term any contact model can carry: WithRolling<M> is
// model M with a rolling torque added, registered beside M (models.hpp), so a
// material pair that declares `rolling_friction > 0` has its contacts in
// another bucket whose kernel computes the torque, and a scene without it runs
// M's kernel unchanged (docs/features_cost.md).
//
// The relative rolling velocity is w_r = w_i - w_j without its component
// along the normal (twisting is not resisted), Ai et al. 2011, Eq. 11; the
// torque M acts on i and -M on j (against a wall, w_j is the wall's spin).
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
// The EPSD spring adds a rotational mode, omega_r^2 = k_r / I_r; as
// I_r >= 1.4 m* R*^2 for spheres (Ai Eq. 13 with R* <= each radius),
// omega_r <= sqrt(k_r-factor / 1.4) mu_r omega_n, which bounds the stability
// limit (1.27 mu_r omega_n with the default 2.25: a sphere on a wall).
// N is the normal force kept >= 0 (an adhesive law's tensile force gives no
// rolling resistance).
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
// The rolling parameters every model carries when rolling_friction is given.
std::vector<ParamSpec> rolling_parameters();
// Whether a parameter name is one of them.
bool is_rolling_parameter(const std::string& name);

struct RollingParams {
  double friction = 0;  // mu_r
  int model = rolling_model::epsd;
  double stiffness = 2.25;  // k_r / (k_n mu_r^2 R*^2)
  double damping = 0;       // eta_r
};

// Whether model M states its normal stiffness at an overlap
// (`static double normal_stiffness(const Params&, double r_star, double overlap)`).
template <typename M, typename = void>
struct has_normal_stiffness : std::false_type {};

template <typename M>
struct has_normal_stiffness<M, std::void_t<decltype(M::normal_stiffness(
                                   std::declval<const typename M::Params&>(), 0.0, 0.0))>>
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
    p.roll.model = static_cast<int>(v.at("rolling_model"));
    p.roll.damping = v.at("rolling_damping");
    // The constant torque has no dashpot: a damping given with it would be echoed in
    // the run header and do nothing.
    if (p.roll.model == rolling_model::constant && p.roll.damping != 0)
      throw InputError(
          fmt::format("rolling_damping = {} acts only with rolling_model = \"epsd\" (the constant "
                      "torque has no dashpot)",
                      p.roll.damping));
    return p;
  }

  template <int D>
  struct History {
    typename M::template History<D> base{};
    Spin<D> rolling = Dim<D>::zero_spin();  // N m, the EPSD spring torque on i
  };

  template <int D>
  static bool touching(const Params& p, const History<D>& h, double overlap) {
    return M::touching(p.base, h.base, overlap);
  }
  static double reach(const Params& p, double r_star) { return M::reach(p.base, r_star); }
  static constexpr bool steps_per_contact_counted = M::steps_per_contact_counted;
  static double rule_time_step(const Params& p, const PairScale& s, double steps_per_contact) {
    return M::rule_time_step(p.base, s, steps_per_contact);
  }
  // The law's own stiffest mode at an overlap, where it says one (has_mode_squared).
  template <class Base = M, class = std::enable_if_t<has_mode_squared<Base>::value>>
  static double mode_squared(const Params& p, const PairScale& s, double overlap) {
    return Base::mode_squared(p.base, s, overlap);
  }
  // The law's own limit, and the rolling spring's: omega_r up to `ratio` times the
  // normal mode's omega_n, so its limit is the normal one's over ratio (a law
  // whose limit also counts its tangential spring says its normal one apart).
  static double stability_limit(const Params& p, const PairScale& s) {
    const double base = M::stability_limit(p.base, s);
    if (p.roll.model != rolling_model::epsd) return base;
    const double ratio = std::sqrt(p.roll.stiffness / 1.4) * p.roll.friction;  // omega_r / omega_n
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

  // k_n of k_r = 2.25 k_n mu_r^2 R*^2.
  static double normal_stiffness_of(const Params& p, double r_star, double overlap,
                                    double normal_force) {
    if constexpr (has_normal_stiffness<M>::value)
      return M::normal_stiffness(p.base, r_star, overlap);
    else
      return overlap > 0 && normal_force > 0 ? normal_force / overlap : 0.0;
  }

  // The rolling torque on i (j feels minus it), after force() of the same
  // step: `normal_force` is its N, `spin_difference` w_i - w_j, `inertia` I_r
  // and `inv_inertia_sum` 1/I_i + 1/I_j (0 for a wall or fixed particle).
  template <int D>
  static Spin<D> rolling_torque(const Params& p, History<D>& h, const ContactState<D>& c,
                                double normal_force, const Spin<D>& spin_difference, double inertia,
                                double inv_inertia_sum) {
    using S = Spin<D>;
    const RollingParams& r = p.roll;
    const double n_force = std::max(normal_force, 0.0);
    const double cap = r.friction * c.effective_radius * n_force;  // M_m
    S w_r = spin_difference;
    if constexpr (D == 3) w_r -= c.normal * c.normal.dot(spin_difference);  // no twisting
    if (r.model == rolling_model::constant) {
      const double speed = std::sqrt(Dim<D>::spin_sq(w_r));
      if (!(speed > 0)) return Dim<D>::zero_spin();
      // A hair less than the whole spin, so that round-off in the integration
      // cannot take it through zero (inf when nothing can turn).
      const double stopping = (1 - 1e-12) * speed / (inv_inertia_sum * c.dt);
      return S(w_r * (-std::min(cap, stopping) / speed));
    }
    const double k_n = normal_stiffness_of(p, c.effective_radius, c.overlap, n_force);
    const double lever = r.friction * c.effective_radius;
    const double k_r = r.stiffness * k_n * lever * lever;
    S spring;
    if constexpr (D == 3)
      spring = rotate_onto_plane<3>(h.rolling, c.normal) - k_r * c.dt * w_r;
    else
      spring = h.rolling - k_r * c.dt * w_r;
    const double spring_sq = Dim<D>::spin_sq(spring);
    if (spring_sq > cap * cap) {  // fully mobilised: the spring slips at M_m, no dashpot
      spring = spring * (cap / std::sqrt(spring_sq));
      h.rolling = spring;
      return spring;
    }
    h.rolling = spring;
    if (r.damping == 0) return spring;
    // The dashpot C_r = 2 eta_r sqrt(I_r k_r) acts on the particles' own inertia: at
    // C_r dt (1/I_i + 1/I_j) > 1 one step would more than stop w_r and, past 2, make
    // it grow step by step (a resting sphere spun up to the torque cap). Held at 1, a
    // dashpot too strong for the step stops the relative spin in one step, as the
    // constant model's torque does.
    const double c_r =
        std::min(2 * r.damping * std::sqrt(inertia * k_r), 1.0 / (inv_inertia_sum * c.dt));
    const S total = spring - c_r * w_r;
    const double total_sq = Dim<D>::spin_sq(total);
    return total_sq > cap * cap ? S(total * (cap / std::sqrt(total_sq))) : total;
  }
};

}  // namespace granule
