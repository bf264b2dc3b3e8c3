// Thornton's frictional auto-adhesive contact (dissertation section 6.3.3; SPEC 3.3):
// JKR normal force, Savkoor-Briggs peeling, then Mindlin-Deresiewicz partial slip
// with N replaced by N + 2Nc and Thornton's two sliding criteria.
//
// Normal (Eqs. 6.12-6.17). The contact radius a is the state. For an overlap alpha
// we solve Eq. 6.14, alpha = a^2/R* - sqrt(2 pi Gamma a / E*), for a on its stable
// branch (a >= a_f, where d(alpha)/da >= 0) and take the JKR force
//   N = 4 E* a^3 / (3 R*) - sqrt(8 pi Gamma E* a^3),
// which is Eqs. 6.12-6.13 solved for N (N' = 4 E* a^3/(3 R*) is the Hertz force of
// the same area) and integrates the incremental Eq. 6.15 exactly. Pull-off force
// Nc = 1.5 pi Gamma R*, reached at a_c^3 = 3 Nc R*/(4 E*) (Eq. 6.17).
//
// Contact formation and separation. A contact forms when the overlap first becomes
// positive: a jumps from 0 to the root of Eq. 6.14 (a^3 = 2 pi Gamma R*^2/E* at
// alpha = 0+, N = -8/9 Nc: the snap-on). It then persists into negative overlap.
// DEM integrates positions, so the contact is displacement-controlled: it passes
// the load-controlled pull-off point a_c = a0/4^{1/3} (N = -Nc, the minimum force)
// stably and separates where Eq. 6.14 has no stable root any more, at the minimum
// of alpha(a): a_f = a0/6^{2/3} = (pi Gamma R*^2/(8 E*))^{1/3}, where
//   alpha_f = -3 a_f^2/R* = -(3/4) (pi^2 Gamma^2 R*/E*^2)^{1/3},  N = -5/9 Nc
// (Thornton and Ning 1998). touching() keeps the contact while alpha > alpha_f.
// (a = a0/4^{1/3} is a_c, not the separation point; its alpha is only -0.36 of
// the same scale.) The neighbour search must therefore see pairs up to |alpha_f|
// apart, or the history is lost early.
//
// Tangential (Eqs. 6.18-6.25). While peeling, T grows without slip, dT = 8 G* a
// d(delta) (Eq. 6.19), with a the peeled radius of Eq. 6.20 (larger root), taken
// by the implicit midpoint rule at the step's middle N and T (force()). Peeling ends, once and for
// all in this contact, when |T| reaches Tc (Eq. 6.21); T then holds Tc, or falls to the sliding
// force if Tc is above it. After peeling the contact radius is a_p of Eq. 6.22 and
// T follows thornton_elastic's Mindlin-Deresiewicz increments (Eqs. 6.5-6.11) with
// N replaced by N + 2Nc, capped by the sliding force: Eq. 6.23 (with N' of 6.24)
// for N < -0.3 Nc, else Eq. 6.25, mu (N + 2Nc).
//
// Gamma = 0 hands the step to thornton_elastic, so the two models agree (to
// round-off: a build that fuses multiply-adds may fuse them differently where
// the shared code is inlined).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "contact/contact_state.hpp"
#include "contact/parameters.hpp"
#include "contact/thornton_elastic.hpp"
#include "core/errors.hpp"

namespace granule {

struct ThorntonJkr {
  static constexpr const char* name = "thornton_jkr";
  static constexpr const char* doc =
      "Thornton frictional auto-adhesive spheres: JKR normal force (pull-off 1.5 pi Gamma R*, "
      "separation at alpha_f), Savkoor-Briggs peeling then Mindlin-Deresiewicz slip with N + 2Nc; "
      "dissertation section 6.3.3, Eqs. 6.12-6.25";
  static constexpr bool adhesive = true;

  static std::vector<ParamSpec> parameters() {
    return {
        // Bounded as thornton_elastic's (thornton_elastic.hpp).
        {"friction", "-", 0.0, 0, ThorntonElastic::friction_limit, true,
         "Coulomb friction coefficient mu (at most 10)"},
        {"surface_energy", "J/m^2", -1.0, -1, unbounded, true,
         "interface energy Gamma (Nc = 1.5 pi Gamma R*); -1: the mean of the two materials' "
         "surface_energy"},
        ThorntonElastic::shrink_rescale_parameter(),
    };
  }

  struct Params {
    ThorntonElastic::Params elastic;  // E*, G*, mu
    double surface_energy;            // Gamma, J/m^2
    // Pair constants of the closed forms below, so that a contact's step needs
    // only cbrt(R*) (kept in its history) besides the Newton solve:
    double k;           // sqrt(2 pi Gamma / E*), Eq. 6.14
    double alpha_coef;  // alpha_f = -alpha_coef cbrt(R*)
    double s_f_coef;    // s_f = s_f_coef cbrt(R*): the fold of Eq. 6.14 in s = sqrt(a)
    double s_hi_coef;   // cbrt(2 k): an upper bracket s_hi = s_hi_coef cbrt(R*)
  };

  // The pair's Gamma: its own value, or (-1) the mean of its materials' values.
  static double surface_energy_in(const ParamValues& v, const PairMaterials& m) {
    const double given = v.at("surface_energy");
    return given == -1.0 ? 0.5 * (m.a.surface_energy + m.b.surface_energy) : given;
  }

  static Params make(const ParamValues& v, const PairMaterials& m) {
    Params p;
    p.elastic = ThorntonElastic::from_materials(v.at("friction"),
                                                ThorntonElastic::shrink_rescale_in(v), m, name);
    const double given = v.at("surface_energy");
    const double gamma = surface_energy_in(v, m);
    if (!(gamma >= 0) || !std::isfinite(gamma))
      throw InputError(fmt::format(
          "{} contact: 'surface_energy' must be >= 0 [J/m^2] (got {}{}); give it in the contact "
          "or as surface_energy of materials '{}' and '{}'",
          name, gamma, given == -1.0 ? ", the mean of the materials' values" : "", m.a.name,
          m.b.name));
    p.surface_energy = gamma;
    const double e_star = p.elastic.e_star;
    p.k = std::sqrt(2 * pi * gamma / e_star);
    p.alpha_coef = 0.75 * std::cbrt(pi * pi * gamma * gamma / (e_star * e_star));
    p.s_f_coef = std::cbrt(0.25 * p.k);
    p.s_hi_coef = std::cbrt(2 * p.k);
    return p;
  }

  template <int D>
  struct History {
    ThorntonElastic::History<D> md;  // T, T*, T**, u, branch, previous N
    double contact_radius = 0;       // a; 0: no contact yet
    double separation_overlap = 0;   // alpha_f of this contact (<= 0)
    bool peeled = false;             // Eq. 6.21 reached: Mindlin-Deresiewicz from now on
    char zero_padding[7] = {};       // written as bytes: zeros, not the heap's (thornton_elastic)
    double cbrt_radius = 0;          // cbrt(R*), taken again only when R* changes (a wall's)
  };

  template <int D>
  static bool touching(const Params&, const History<D>& h, double overlap) {
    return overlap > 0 || (h.contact_radius > 0 && overlap > h.separation_overlap);
  }

  // How far apart (m) the surfaces of a contact of effective radius up to
  // r_star can be while it lasts: -alpha_f. The neighbour skin must exceed it.
  static double reach(const Params& p, double r_star) {
    return p.surface_energy > 0 ? -separation_overlap(p.surface_energy, r_star, p.elastic.e_star)
                                : 0.0;
  }

  static constexpr bool steps_per_contact_counted = ThorntonElastic::steps_per_contact_counted;
  static double rule_time_step(const Params& p, const PairScale& s, double steps_per_contact) {
    return ThorntonElastic::rule_time_step(p.elastic, s, steps_per_contact);
  }
  static double stability_limit(const Params& p, const PairScale& s) {
    return ThorntonElastic::stability_limit(p.elastic, s);
  }
  // omega^2 of the stiffest mode at an overlap: the JKR contact radius there, which
  // is a0 (Eq. 6.14 at N = 0) already at zero overlap.
  static double mode_squared(const Params& p, const PairScale& s, double overlap) {
    // Peeling resists sliding even at mu = 0 (Eqs. 6.18-6.21): a tangential mode
    // wherever the pair sticks or rubs.
    return ThorntonElastic::stiffest_mode_squared(p.elastic, s, mode_radius(p, s, overlap),
                                                  p.elastic.friction > 0 || p.surface_energy > 0);
  }
  // The normal mode's alone (the rolling term scales it, rolling.hpp).
  static double normal_mode_squared(const Params& p, const PairScale& s, double overlap) {
    return ThorntonElastic::stiffest_mode_squared(p.elastic, s, mode_radius(p, s, overlap), false);
  }
  // The contact radius the modes above take at an overlap.
  static double mode_radius(const Params& p, const PairScale& s, double overlap) {
    const double r_star = s.effective_radius, alpha = std::max(overlap, 0.0);
    return p.surface_energy > 0
               ? contact_radius_for(alpha, p.surface_energy, r_star, p.elastic.e_star, 0)
               : std::sqrt(r_star * alpha);
  }

  // The load and normal stiffness that rolling and twisting resistance take
  // (rolling.hpp), after force() of the same step:
  //  - load N + 2Nc, the load the tangential law's slip takes after peeling
  //    (Eqs. 6.22-6.25), so that a contact at rest (N = 0) still resists
  //    rolling and twisting, by mu_r R* 2Nc (Dominik and Tielens' adhesive
  //    rolling resistance 6 Nc xi_crit at mu_r R* = 3 xi_crit);
  //  - stiffness 4 E* a / 3, the secant N' / alpha' of the Hertz force of the
  //    same contact area (Eq. 6.13, alpha' = a^2 / R*), which follows a into
  //    tension, where the secant N / alpha of the JKR force is meaningless.
  // At Gamma = 0 both are thornton_elastic's: N >= 0 and the secant N / alpha.
  struct Resisting {
    double load;       // N
    double stiffness;  // N/m
  };
  template <int D>
  static Resisting resisting(const Params& p, const History<D>& h, double r_star, double overlap,
                             double normal) {
    if (!(p.surface_energy > 0) || !(h.contact_radius > 0))
      return {std::max(normal, 0.0), overlap > 0 && normal > 0 ? normal / overlap : 0.0};
    return {std::max(0.0, normal + 2 * pull_off_force(p.surface_energy, r_star)),
            4.0 / 3.0 * p.elastic.e_star * h.contact_radius};
  }

  // Closed forms for a pair (R*, E*, Gamma), used by force() and by tests.
  static double pull_off_force(double gamma, double r_star) { return 1.5 * pi * gamma * r_star; }
  // a0: contact radius at N = 0.
  static double zero_load_radius(double gamma, double r_star, double e_star) {
    return std::cbrt(4.5 * pi * gamma * r_star * r_star / e_star);
  }
  // alpha_f: the overlap at which the contact separates (<= 0).
  static double separation_overlap(double gamma, double r_star, double e_star) {
    return -0.75 * std::cbrt(pi * pi * gamma * gamma * r_star / (e_star * e_star));
  }
  // N for a contact radius a (Eqs. 6.12-6.13 solved for N).
  static double jkr_force(double a, double gamma, double r_star, double e_star) {
    const double a3 = a * a * a;
    return 4 * e_star * a3 / (3 * r_star) - std::sqrt(8 * pi * gamma * e_star * a3);
  }
  // The stable root a of Eq. 6.14 for overlap alpha > alpha_f, by safeguarded Newton
  // iteration in s = sqrt(a), where f(s) = s^4/R* - k s - alpha (k = sqrt(2 pi Gamma/E*))
  // is convex and increasing on [s_f, inf), s_f^3 = k R*/4. `guess` is the last a (or 0).
  static double contact_radius_for(double alpha, double gamma, double r_star, double e_star,
                                   double guess) {
    const double k = std::sqrt(2 * pi * gamma / e_star);
    return solve_contact_radius(alpha, r_star, k, std::cbrt(0.25 * k * r_star),
                                std::cbrt(2 * k * r_star), guess);
  }
  // The same with the fold s_f and the bracket s_hi = cbrt(2 k R*) given.
  static double solve_contact_radius(double alpha, double r_star, double k, double s_f, double s_hi,
                                     double guess) {
    // f(s) > 0 beyond s_hi: s^4/(2R*) >= k s and, for alpha > 0, s^4/(2R*) >= alpha.
    double hi = s_hi;
    if (alpha > 0) hi = std::max(hi, std::sqrt(std::sqrt(2 * alpha * r_star)));
    double lo = s_f;
    const double inv_r = 1.0 / r_star;
    const double g = std::sqrt(guess > 0 ? guess : 0.0);
    double s = (g > lo && g < hi) ? g : hi;
    for (int it = 0; it < 200; ++it) {
      const double s2 = s * s;
      const double f = s2 * s2 * inv_r - k * s - alpha;
      if (f == 0) break;
      if (f > 0)
        hi = s;
      else
        lo = s;
      const double slope = 4 * s2 * s * inv_r - k;
      double next = slope > 0 ? s - f / slope : 0.5 * (lo + hi);
      // A Newton step at round-off size is convergence; it may land on lo or hi
      // (it is s itself), which must not send it back to bisection.
      if (slope > 0 && std::abs(next - s) <= 1e-15 * s) {
        s = next;
        break;
      }
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      const bool done = std::abs(next - s) <= 1e-15 * s || hi - lo <= 1e-15 * hi;
      s = next;
      if (done) break;
    }
    return s * s;
  }
  // The root of a = radius_of(a) (Eq. 6.20 at the midpoint T of Eq. 6.19's
  // step): fixed-point steps from `guess`, which contract where the step is
  // small against the distance to Tc; else bisection between the radius at Tc
  // (lo, where radius_of(lo) >= lo) and at T = 0 (hi, radius_of(hi) <= hi),
  // which `bracket` gives.
  template <typename RadiusOf, typename Bracket>
  static double peeling_radius(const RadiusOf& radius_of, double guess, const Bracket& bracket) {
    double a = guess;
    for (int k = 0; k < 12; ++k) {
      const double next = radius_of(a);
      if (std::abs(next - a) <= 1e-14 * a) return next;
      a = next;
    }
    auto [lo, hi] = bracket();
    for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
      const double mid = 0.5 * (lo + hi);
      (radius_of(mid) > mid ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  // The sliding force after peeling: Eq. 6.23 with N' of Eq. 6.24 for N < -0.3 Nc,
  // else Eq. 6.25.
  static double sliding_force(double mu, double normal, double nc) {
    if (normal < -0.3 * nc) {
      const double n1 = normal + 2 * nc + 2 * std::sqrt(std::max(0.0, normal * nc + nc * nc));
      if (!(n1 > 0)) return 0;
      const double base = 1 - (n1 - normal) / (3 * n1);
      return base > 0 ? mu * n1 * base * std::sqrt(base) : 0.0;
    }
    return mu * std::max(0.0, normal + 2 * nc);
  }

  template <int D>
  static ContactForce<D> force(const Params& p, History<D>& h, const ContactState<D>& c) {
    const double gamma = p.surface_energy;
    if (gamma == 0) {  // no adhesion: exactly thornton_elastic
      h.contact_radius = 0;
      h.separation_overlap = 0;
      h.peeled = false;
      return ThorntonElastic::force<D>(p.elastic, h.md, c);
    }
    ContactForce<D> out;
    const double r = c.effective_radius, e = p.elastic.e_star, g = p.elastic.g_star;
    const double mu = p.elastic.friction;
    const bool fresh = !(h.contact_radius > 0);
    if (fresh && !(c.overlap > 0)) {  // a contact forms at zero overlap
      h = History<D>{};
      return out;
    }
    // A pair's R* is constant; a sphere sliding along a cone, or from a polyline's
    // segment onto its arc, meets another one, and the separation overlap alpha_f and
    // the solver's brackets (Eqs. 6.14-6.17) go with the R* of the step.
    const double cube = h.cbrt_radius * h.cbrt_radius * h.cbrt_radius;
    if (fresh || !(std::abs(cube - r) <= 1e-12 * r)) h.cbrt_radius = std::cbrt(r);
    const double cbrt_r = h.cbrt_radius;
    const double alpha_f = -p.alpha_coef * cbrt_r;  // separation_overlap(gamma, r, e)
    if (!(c.overlap > alpha_f)) {                   // no longer in contact
      h = History<D>{};
      return out;
    }
    // Normal, Eqs. 6.12-6.17.
    const double a = solve_contact_radius(c.overlap, r, p.k, p.s_f_coef * cbrt_r,
                                          p.s_hi_coef * cbrt_r, h.contact_radius);
    const double normal = jkr_force(a, gamma, r, e);
    h.contact_radius = a;
    h.separation_overlap = alpha_f;
    out.normal = normal;

    const double nc = pull_off_force(gamma, r);
    const double n_eff = std::max(0.0, normal + 2 * nc);  // N + 2Nc (>= Nc on the stable branch)
    const double dn = fresh ? 0.0 : normal - h.md.previous_normal;
    h.md.previous_normal = normal;
    const double slide = sliding_force(mu, normal, nc);

    // A contact that carried T under Gamma = 0 (a surface energy ramped up from
    // zero while it lasts) is past peeling where T already reaches Tc of the new
    // Gamma (Eq. 6.21): it goes on as a peeled contact from its Mindlin-
    // Deresiewicz state, whose limit mu (N + 2Nc) only grew, rather than taking
    // peeling's first step, which would cut T to Tc in one step.
    if (fresh && !h.peeled && h.md.tangential.squaredNorm() > 0) {
      const double t_c = 4 * std::sqrt(std::max(0.0, g / e * nc * (normal + nc)));
      h.peeled = rotate_onto_plane<D>(h.md.tangential, c.normal).norm() >= t_c;
    }
    if (h.peeled) {
      const double a_p = std::cbrt(3 * r * n_eff / (4 * e));  // Eq. 6.22
      out.tangential = ThorntonElastic::mindlin_deresiewicz<D>(
          h.md, c, 8 * g * a_p, mu * n_eff, mu * dn, slide, p.elastic.shrink_rescale);
      return out;
    }
    // Peeling, Eqs. 6.18-6.21.
    Vec<D> t = rotate_onto_plane<D>(h.md.tangential, c.normal);
    // Eq. 6.20's contact radius under N (and N + 2Nc) and T.
    auto radius_under = [&](double n, const Vec<D>& t_of) {
      const double under =
          std::sqrt(std::max(0.0, 4 * nc * (n + nc) - t_of.squaredNorm() * e / (4 * g)));
      return std::cbrt(3 * r / (4 * e) * (std::max(0.0, n + 2 * nc) + under));
    };
    if (p.elastic.shrink_rescale && !fresh) {
      // As in mindlin_deresiewicz: a shrinking contact's T scales with its radius,
      // a_t / a_t of the last step. Eq. 6.19 alone unloads T built on the larger
      // contact at the smaller one's stiffness, which returns more work than it
      // stored: a closed path of (overlap, displacement) ends at another T, and an
      // oblique adhesive impact gains tangential energy.
      const double before = radius_under(normal - dn, t), now = radius_under(normal, t);
      if (now < before && before > 0) t *= now / before;
    }
    const double t_c = 4 * std::sqrt(std::max(0.0, g / e * nc * (normal + nc)));  // Eq. 6.21
    // Eq. 6.19, dT = 8 G* a_t d(delta), with a_t of Eq. 6.20 falling as |T| grows:
    // by the implicit midpoint rule, a_t taken at (T + T_new) / 2 and the step's
    // middle N. Taken at the step's start T (explicit Euler), each step out
    // overshoots and each step back undershoots, so a contact sheared to and fro
    // returns more work than it stored, at a rate proportional to dt, and an
    // undamped adhesive cluster left at rest gains energy. The midpoint rule is
    // symmetric: a step back by the same slip retraces the step out, so at a
    // fixed N a path retraced in equal steps returns T to round-off.
    const Vec<D> per_radius = 8 * g * (c.tangential_velocity * c.dt);  // T_new = T + a_t * this
    const double n_mid = normal - 0.5 * dn;
    const double a_t =
        per_radius.squaredNorm() > 0
            ? peeling_radius(
                  [&](double a) { return radius_under(n_mid, Vec<D>(t + 0.5 * a * per_radius)); },
                  radius_under(normal, t),
                  [&] {
                    return std::pair{std::cbrt(3 * r / (4 * e) * std::max(0.0, n_mid + 2 * nc)),
                                     radius_under(n_mid, Vec<D>::Zero())};
                  })
            : 0.0;                        // no slip: T stays
    Vec<D> t_new = t + a_t * per_radius;  // Eq. 6.19
    const double t_mag = t_new.norm();
    if (t_mag > 0 && t_mag >= t_c) {
      // Peeling complete (Eq. 6.22): T stops at Tc, or falls to the sliding force.
      h.peeled = true;
      const double keep = std::min(t_c, slide);
      t_new *= keep / t_mag;
      h.md.branch = ThorntonElastic::loading;
      h.md.load_direction =
          t_new.squaredNorm() > 0 ? Vec<D>(t_new / t_new.norm()) : Vec<D>(Vec<D>::Zero());
      h.md.reversal.setZero();
      h.md.reversal2.setZero();
    }
    h.md.tangential = t_new;
    out.tangential = t_new;
    return out;
  }
};

// No gap the compiler fills: a history's bytes are all members (zero_padding).
static_assert(sizeof(ThorntonJkr::History<2>) == sizeof(ThorntonElastic::History<2>) + 32);
static_assert(sizeof(ThorntonJkr::History<3>) == sizeof(ThorntonElastic::History<3>) + 32);

}  // namespace granule
