// Thornton's frictional elastic contact (dissertation section 6.3.2; SPEC 3.2):
// Hertz normal force and the incremental Mindlin-Deresiewicz tangential force.
//
// Normal (Eqs. 6.3-6.4): N = 4/3 E* sqrt(R*) alpha^{3/2}, a = sqrt(alpha R*). The
// closed form is used at every step (the incremental second line of 6.3,
// dN = 2 E* a d(alpha), integrates to the same thing and would only add drift).
//
// Tangential (Eqs. 6.5-6.11): dT = K_T d(delta) with K_T = 8 G* a theta +- mu (1 -
// theta) dN / d(delta). We never form dN / d(delta) (it is infinite for d(delta) = 0):
// the increment is written as dT = 8 G* a theta d(delta) +- mu dN (1 - theta), which
// is Eq. 6.6 multiplied out. As in Walton-Braun, T and the reversal values T*, T**
// are vectors in the tangent plane, carried onto the current plane every step;
// the loading/unloading/reloading logic reads them along u, the sense of the
// displacement increment on T's line of action, and the part of the increment
// perpendicular to T gets the no-slip stiffness 8 G* a. Read along u, the three
// branches of Eq. 6.6 share one formula, dT_u = 8 G* a theta |d(delta)| + mu dN (1 -
// theta): unloading's "-" in Eq. 6.6 is the "+" of loading seen from the other side.
//
// Branch bookkeeping (not spelled out in the dissertation; Masing's rules, as in
// Thornton and Yin 1991): the first increment loads; a reversal while loading
// starts unloading with T* = T; a reversal while unloading starts reloading with
// T** = T; a reversal while reloading starts a new unloading with T* = T (inner
// loops are not nested further). Reloading that gets back to T*, or unloading that
// gets to -T* (where the unloading curve meets the virgin curve of the other
// side), continues as loading. Eq. 6.11 moves the reversal points outwards by
// mu dN along the direction in which they were reached, on the steps that slip
// (theta < 1): the memory of a slip annulus moves with the annulus, and a step
// with theta = 1 (Eq. 6.7, or a cube of 1 or more) changes neither. (Moved on every step, a
// reversal reached without slip, T* = T ~ 0, runs out by mu dN a step while N
// rises, and as N falls Eq. 6.6's mu dN (1 - theta), theta < 1 by Eq. 6.9 with
// T* - T near mu N, pulls T out to a finite force whatever the slip:
// docs/contact_models.md gives the numbers.)
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_state.hpp"
#include "contact/parameters.hpp"
#include "core/errors.hpp"

namespace granule {

struct ThorntonElastic {
  static constexpr double friction_limit = 10;
  static constexpr const char* name = "thornton_elastic";
  static constexpr const char* doc =
      "Thornton frictional elastic spheres: Hertz normal force and incremental "
      "Mindlin-Deresiewicz tangential force with loading/unloading/reloading; dissertation "
      "section 6.3.2, Eqs. 6.3-6.11. E* and G* come from the materials' young and poisson";
  static constexpr bool adhesive = false;

  static std::vector<ParamSpec> parameters() {
    return {
        // Up to 10 no impact gains energy beyond the step's own error, which
        // falls with the step (tests/contact/test_thornton_friction.cpp); no
        // powder has a friction coefficient near it.
        {"friction", "-", 0.0, 0, ThorntonElastic::friction_limit, true,
         "Coulomb friction coefficient mu (at most 10)"},
        shrink_rescale_parameter(),
    };
  }
  // Shared with thornton_jkr, whose tangential law this is.
  static ParamSpec shrink_rescale_parameter() {
    return {"shrink_rescale",
            "-",
            0,
            0,
            1,
            true,
            "1: while N falls, T, T* and T** scale with the contact radius (a / a_prev) in place "
            "of Eq. 6.6's mu dN terms and Eq. 6.11 (Thornton, Cummins and Cleary 2013), which "
            "converges with the step at any friction (and thornton_jkr's peeling T of Eq. 6.19 "
            "with a_t); 0: Eqs. 6.6-6.11 and 6.19 as the dissertation writes them",
            true};
  }

  // Off unless given (make() is also called with a law's values alone).
  static bool shrink_rescale_in(const ParamValues& v) {
    const auto it = v.find("shrink_rescale");
    return it != v.end() && it->second != 0;
  }

  struct Params {
    double e_star;        // Pa, 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2
    double g_star;        // Pa, 1/G* = (2-nu1)/G1 + (2-nu2)/G2
    double friction;      // mu
    bool shrink_rescale;  // shrink_rescale_parameter()
  };

  // E* and G* of a material pair. `model` names the model in error messages.
  static Params from_materials(double friction, bool shrink_rescale, const PairMaterials& m,
                               const char* model) {
    for (const Material* mat : {&m.a, &m.b}) {
      if (!(mat->young > 0))
        throw InputError(fmt::format(
            "{} contact: material '{}' needs a Young's modulus 'young' > 0 [Pa] (got {})", model,
            mat->name, mat->young));
      if (!(mat->poisson > -1 && mat->poisson <= 0.5))
        throw InputError(fmt::format(
            "{} contact: material '{}' has Poisson's ratio 'poisson' = {}, outside (-1, 0.5]",
            model, mat->name, mat->poisson));
    }
    const Material &a = m.a, &b = m.b;
    Params p;
    p.e_star =
        1.0 / ((1 - a.poisson * a.poisson) / a.young + (1 - b.poisson * b.poisson) / b.young);
    const double g_a = a.young / (2 * (1 + a.poisson)),
                 g_b = b.young / (2 * (1 + b.poisson));  // 6.2
    // The dissertation prints 1/G* = (1-nu1^2)/G1 + (1-nu2^2)/G2 under Eq. 6.6, a typo:
    // Mindlin's tangential stiffness 8 G* a needs 1/G* = (2-nu1)/G1 + (2-nu2)/G2
    // (Johnson 1985, Eq. 7.30; Thornton and Yin 1991), which is what we use.
    p.g_star = 1.0 / ((2 - a.poisson) / g_a + (2 - b.poisson) / g_b);
    p.friction = friction;
    p.shrink_rescale = shrink_rescale;
    return p;
  }

  static Params make(const ParamValues& v, const PairMaterials& m) {
    return from_materials(v.at("friction"), ThorntonElastic::shrink_rescale_in(v), m, name);
  }

  // Branches of Eqs. 6.8-6.10.
  static constexpr int loading = 0, unloading = 1, reloading = 2;

  template <int D>
  struct History {
    Vec<D> tangential = Vec<D>::Zero();      // T, force on i
    Vec<D> reversal = Vec<D>::Zero();        // T*: where loading turned to unloading (Eq. 6.9)
    Vec<D> reversal2 = Vec<D>::Zero();       // T**: where unloading turned to reloading (Eq. 6.10)
    Vec<D> load_direction = Vec<D>::Zero();  // u: unit sense of the last increment on T's line
    int branch = loading;
    // Histories are written to checkpoints and output as their bytes: the gap
    // before the next double is a member, so that it holds zeros, not whatever
    // the heap held (the same run then writes the same file).
    std::int32_t zero_padding = 0;
    double previous_normal = 0;  // N of the last step, for dN
  };

  template <int D>
  static bool touching(const Params&, const History<D>&, double overlap) {
    return overlap > 0;
  }

  // What rule_time_step's n counts (the run header says it): not steps per
  // contact, as a Hertz contact's duration falls with the closing speed.
  static constexpr bool steps_per_contact_counted = false;
  // 20% of the Rayleigh step of Eq. 6.1 at the default n = 40.
  static double rule_time_step(const Params&, const PairScale& s, double steps_per_contact) {
    return 0.2 * s.rayleigh_time * 40.0 / steps_per_contact;
  }
  static double stability_limit(const Params& p, const PairScale& s) {
    return softer_partner_limit(s, p.e_star, p.g_star);
  }
  // omega^2 of the contact's stiffest mode at an overlap (as HertzMindlin's: the
  // no-slip tangential spring 8 G* a, its mass m* / 3.5).
  static double mode_squared(const Params& p, const PairScale& s, double overlap) {
    return stiffest_mode_squared(p, s, std::sqrt(s.effective_radius * std::max(overlap, 0.0)),
                                 p.friction > 0);
  }
  // The normal mode's alone (the rolling term scales it, rolling.hpp).
  static double normal_mode_squared(const Params& p, const PairScale& s, double overlap) {
    return stiffest_mode_squared(p, s, std::sqrt(s.effective_radius * std::max(overlap, 0.0)),
                                 false);
  }
  // The same for a contact radius a (thornton_jkr's, which a contact at zero load has
  // too); the tangential mode only where a tangential force can act.
  static double stiffest_mode_squared(const Params& p, const PairScale& s, double a,
                                      bool tangential) {
    return std::max(2 * p.e_star, tangential ? 3.5 * 8 * p.g_star : 0.0) * a / s.effective_mass;
  }

  // One increment of Eqs. 6.5-6.11 on h's tangential state. k0 = 8 G* a (no-slip
  // stiffness), mu_n = mu N of Eqs. 6.8-6.10, mu_dn = mu dN, cap = the sliding force
  // |T| may not exceed (mu N here; thornton_jkr passes N + 2Nc and Eq. 6.23/6.25).
  // Needs N of the current step (the dissertation updates N and a first).
  // shrink_rescale: while N falls, T, T* and T** are scaled by a / a_prev, which is
  // (N / N_prev)^(1/3) for the N of mu_n (Hertz, and N + 2Nc of Eq. 6.22), and the
  // increment follows Eqs. 6.6-6.10 at dN = 0, Eq. 6.11 idle. Without it, a falling N
  // releases T only where the step's mu |dN| exceeds a finite force (Eq. 6.7's and the
  // clamped cube's test), a threshold that shrinks with the step: near-normal impacts
  // at high friction then need a step finer than 1 / Psi_1 contacts' worth to converge
  // (docs/contact_models.md).
  template <int D>
  static Vec<D> mindlin_deresiewicz(History<D>& h, const ContactState<D>& c, double k0, double mu_n,
                                    double mu_dn, double cap, bool shrink_rescale = false) {
    if (!(mu_n > 0) || !(cap > 0)) {  // no friction, or N = 0: |T| <= 0
      h.tangential.setZero();
      h.reversal.setZero();
      h.reversal2.setZero();
      h.load_direction.setZero();
      h.branch = loading;
      return h.tangential;
    }
    // Carry T, T*, T** and u onto the current tangent plane (Eqs. 3.7-3.8).
    Vec<D> t = rotate_onto_plane<D>(h.tangential, c.normal);
    Vec<D> star = rotate_onto_plane<D>(h.reversal, c.normal);
    Vec<D> star2 = rotate_onto_plane<D>(h.reversal2, c.normal);
    const Vec<D> previous_u = rotate_onto_plane<D>(h.load_direction, c.normal);
    if (shrink_rescale && mu_dn < 0) {  // the contact shrinks: a / a_prev
      const double shrink = std::cbrt(mu_n / (mu_n - mu_dn));
      t *= shrink, star *= shrink, star2 *= shrink;
      mu_dn = 0;
    }

    const Vec<D> slip = c.tangential_velocity * c.dt;  // d(delta), Eq. 3.10
    const double t_mag = t.norm(), slip_mag = slip.norm();
    // T's line of action; for T = 0 the slip, and with no slip either the last sense.
    Vec<D> line;
    if (t_mag > 0)
      line = t / t_mag;
    else if (slip_mag > 0)
      line = slip / slip_mag;
    else
      line = previous_u;
    const double slip_par = slip.dot(line);
    const Vec<D> slip_perp = slip - slip_par * line;
    // u: the sense of this increment along the line; with no parallel slip (only dN
    // acts) the branch and its sense stay as they were.
    Vec<D> u;
    if (slip_par > 0)
      u = line;
    else if (slip_par < 0)
      u = -line;
    else
      u = previous_u.dot(line) < 0 ? Vec<D>(-line) : line;

    int branch = h.branch;
    if (slip_par != 0) {
      if (previous_u.squaredNorm() == 0) {
        branch = loading;                  // first increment of this contact
      } else if (u.dot(previous_u) < 0) {  // the displacement reversed
        if (branch == unloading) {
          branch = reloading;
          star2 = t;
        } else {
          branch = unloading;
          star = t;
        }
      }
    }
    const double t_u = t.dot(u), star_u = star.dot(u), star2_u = star2.dot(u);
    // Masing's memory: back on the curve this branch branched off from.
    if (branch == reloading && t_u >= star_u) branch = loading;
    if (branch == unloading && t_u >= -star_u) branch = loading;

    double theta = 1;                // Eq. 6.7: no slip while |dT| < mu dN
    if (!(k0 * slip_mag < mu_dn)) {  // partial slip
      double cube;
      if (branch == loading)
        cube = 1 - (t_u + mu_dn) / mu_n;  // Eq. 6.8
      else if (branch == unloading)
        cube = 1 - (t_u - star_u + 2 * mu_dn) / (2 * mu_n);  // Eq. 6.9, read along u
      else
        cube = 1 - (t_u - star2_u + 2 * mu_dn) / (2 * mu_n);  // Eq. 6.10
      cube = cube < 0 ? 0.0 : (cube > 1 ? 1.0 : cube);
      theta = std::cbrt(cube);
    }
    // Eqs. 6.5-6.6 along u; the perpendicular part of the increment does not slip.
    Vec<D> t_new = t + (k0 * theta * std::abs(slip_par) + mu_dn * (1 - theta)) * u + k0 * slip_perp;

    // Eq. 6.11: the reversal points move outwards by mu dN (T* was reached moving
    // against u while unloading, along u while reloading; T** against u), on a
    // step that slips (theta < 1; the header says why).
    const bool slips = theta < 1;
    if (slips && branch == unloading) {
      star -= mu_dn * u;
    } else if (slips && branch == reloading) {
      star += mu_dn * u;
      star2 -= mu_dn * u;
    }
    // |T| <= sliding force; so are the reversal values (they are forces T once had).
    auto cap_at = [cap](Vec<D>& v) {
      const double sq = v.squaredNorm();
      if (sq > cap * cap) v *= cap / std::sqrt(sq);
    };
    cap_at(t_new);
    cap_at(star);
    cap_at(star2);

    h.tangential = t_new;
    h.reversal = star;
    h.reversal2 = star2;
    if (u.squaredNorm() > 0) h.load_direction = u;
    h.branch = branch;
    return t_new;
  }

  template <int D>
  static ContactForce<D> force(const Params& p, History<D>& h, const ContactState<D>& c) {
    ContactForce<D> out;
    const double alpha = c.overlap;
    if (!(alpha > 0)) {  // the engine does not call us here; be safe if someone does
      h = History<D>{};
      return out;
    }
    const double a = std::sqrt(alpha * c.effective_radius);  // Eq. 6.4
    const double normal = 4.0 / 3.0 * p.e_star * a * alpha;  // Eq. 6.3: 4/3 E* R*^1/2 alpha^3/2
    out.normal = normal;
    const double dn = normal - h.previous_normal;  // previous N = 0 for a new contact
    h.previous_normal = normal;
    const double mu = p.friction;
    out.tangential = mindlin_deresiewicz<D>(h, c, 8 * p.g_star * a, mu * normal, mu * dn,
                                            mu * normal, p.shrink_rescale);
    return out;
  }

  // force() for batches of contacts (contact_batch.hpp; thornton_elastic_batch.hpp).
  // History<D> as arrays; the branch as a double (0, 1, 2), so that the lanes'
  // selects on it stay in vector registers beside the forces.
  struct BatchHistory3 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double tx[lanes], ty[lanes], tz[lanes];  // T
    alignas(64) double rx[lanes], ry[lanes], rz[lanes];  // T*
    alignas(64) double qx[lanes], qy[lanes], qz[lanes];  // T**
    alignas(64) double ux[lanes], uy[lanes], uz[lanes];  // u
    alignas(64) double branch[lanes], previous_normal[lanes];
    void load(int l, const History<3>& h) {
      tx[l] = h.tangential.x(), ty[l] = h.tangential.y(), tz[l] = h.tangential.z();
      rx[l] = h.reversal.x(), ry[l] = h.reversal.y(), rz[l] = h.reversal.z();
      qx[l] = h.reversal2.x(), qy[l] = h.reversal2.y(), qz[l] = h.reversal2.z();
      ux[l] = h.load_direction.x(), uy[l] = h.load_direction.y(), uz[l] = h.load_direction.z();
      branch[l] = h.branch, previous_normal[l] = h.previous_normal;
    }
    void store(int l, History<3>& h) const {
      h.tangential = Vec<3>(tx[l], ty[l], tz[l]);
      h.reversal = Vec<3>(rx[l], ry[l], rz[l]);
      h.reversal2 = Vec<3>(qx[l], qy[l], qz[l]);
      h.load_direction = Vec<3>(ux[l], uy[l], uz[l]);
      h.branch = static_cast<int>(branch[l]), h.previous_normal = previous_normal[l];
    }
    void pad(int l) {
      tx[l] = ty[l] = tz[l] = rx[l] = ry[l] = rz[l] = 0;
      qx[l] = qy[l] = qz[l] = ux[l] = uy[l] = uz[l] = 0;
      branch[l] = loading, previous_normal[l] = 0;
    }
  };
  // 2D: the vectors as History<2> keeps them (the batch reads them along t).
  struct BatchHistory2 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double tx[lanes], ty[lanes];  // T
    alignas(64) double rx[lanes], ry[lanes];  // T*
    alignas(64) double qx[lanes], qy[lanes];  // T**
    alignas(64) double ux[lanes], uy[lanes];  // u
    alignas(64) double branch[lanes], previous_normal[lanes];
    void load(int l, const History<2>& h) {
      tx[l] = h.tangential.x(), ty[l] = h.tangential.y();
      rx[l] = h.reversal.x(), ry[l] = h.reversal.y();
      qx[l] = h.reversal2.x(), qy[l] = h.reversal2.y();
      ux[l] = h.load_direction.x(), uy[l] = h.load_direction.y();
      branch[l] = h.branch, previous_normal[l] = h.previous_normal;
    }
    void store(int l, History<2>& h) const {
      h.tangential = Vec<2>(tx[l], ty[l]);
      h.reversal = Vec<2>(rx[l], ry[l]);
      h.reversal2 = Vec<2>(qx[l], qy[l]);
      h.load_direction = Vec<2>(ux[l], uy[l]);
      h.branch = static_cast<int>(branch[l]), h.previous_normal = previous_normal[l];
    }
    void pad(int l) {
      tx[l] = ty[l] = rx[l] = ry[l] = qx[l] = qy[l] = ux[l] = uy[l] = 0;
      branch[l] = loading, previous_normal[l] = 0;
    }
  };
  template <bool Uniform>
  struct LaneParams;
  static void force_batch(const Params* const lane[], BatchHistory3& h, ContactBatch<3>& c);
  static void force_batch(const Params* const lane[], BatchHistory2& h, ContactBatch<2>& c);
  // The law reads no mass, so the batch never fetches the pair's masses
  // (contact_batch.hpp: batch_needs_mass).
  template <typename H>
  static bool batch_needs_mass(const H&) {
    return false;
  }
};

// No gap the compiler fills: a history's bytes are all members (zero_padding).
static_assert(sizeof(ThorntonElastic::History<2>) == 4 * sizeof(Vec<2>) + 16);
static_assert(sizeof(ThorntonElastic::History<3>) == 4 * sizeof(Vec<3>) + 16);

}  // namespace granule

#include "contact/thornton_elastic_batch.hpp"
