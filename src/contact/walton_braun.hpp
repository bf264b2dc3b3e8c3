// Walton-Braun partially latching spring with incrementally slipping friction
// (dissertation section 3.3; SPEC 3.1 settles the details).
//
// Normal (Eqs. 3.1-3.2): load along K1, unload along K2 = K1 / e^2 towards the
// permanent set a0 = a_max (1 - K1/K2); reloading follows the K2 line until it
// meets the K1 line at a_max, then K1 again. Never tensile.
//
// Tangential: the 13 steps of section 3.3 (Eqs. 3.3-3.17). We keep T and the
// reversal value T* as vectors in the tangent plane, so that both rotate with
// the contact (steps 2-3) and T* can be read along any direction. The loading
// direction u is the direction of the parallel slip increment; Eq. 3.3's two
// branches are the same formula read along u (for T decreasing, u = -t and the
// signs of T and T* flip), which keeps the hysteresis right when T passes
// through zero and its own direction flips.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <type_traits>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_state.hpp"
#include "contact/parameters.hpp"
#include "core/errors.hpp"

namespace granule {

struct WaltonBraun {
  static constexpr const char* name = "walton_braun";
  static constexpr const char* doc =
      "Walton-Braun partially latching spring (K1 loading, K2 = K1/e^2 unloading) with "
      "incrementally slipping friction; dissertation section 3.3, Eqs. 3.1-3.17";
  static constexpr bool adhesive = false;
  // Stiffnesses are given, not derived from the pair's size or mass.
  static constexpr bool uses_effective_mass = false;
  static constexpr bool uses_effective_radius = false;

  static std::vector<ParamSpec> parameters() {
    return {
        {"k_load", "N/m", required, 0, unbounded, false,
         "loading stiffness K1 (Eq. 3.2); Eq. 4.2 gives 0.01 pi E r"},
        {"restitution", "-", required, 0, 1, false,
         "coefficient of restitution e = sqrt(K1/K2), Eq. 3.1"},
        {"friction", "-", 0.0, 0, unbounded, true, "Coulomb friction coefficient mu"},
        {"tangential_ratio", "-", 0.8, 0, unbounded, false,
         "tau: initial tangential over normal stiffness, Eq. 3.4; the Mindlin value "
         "2(1-nu)/(2-nu) is 0.8 for PMMA (nu = 0.35)"},
        {"slip_exponent", "-", 1.0, 0, unbounded, false, "nu: exponent of Eq. 3.3 (usually 1)"},
    };
  }

  struct Params {
    double k_load, k_unload, friction, tangential_ratio, slip_exponent;
    double permanent_set_fraction;  // 1 - K1/K2: a0 = a_max * this
  };

  static Params make(const ParamValues& v, const PairMaterials&) {
    Params p;
    p.k_load = v.at("k_load");
    double e = v.at("restitution");
    p.k_unload = p.k_load / (e * e);  // Eq. 3.1
    if (!std::isfinite(p.k_unload))
      throw InputError(fmt::format(
          "walton_braun contact: restitution = {:.4g} makes the unloading stiffness K2 = K1 / e^2 "
          "(Eq. 3.1) overflow for k_load = {:.4g} N/m; give a larger restitution",
          e, p.k_load));
    p.friction = v.at("friction");
    p.tangential_ratio = v.at("tangential_ratio");
    p.slip_exponent = v.at("slip_exponent");
    p.permanent_set_fraction = 1.0 - p.k_load / p.k_unload;
    return p;
  }

  // 3D: T, T* and u are vectors in the tangent plane, carried along as the
  // contact turns (steps 2-3).
  struct History3 {
    Vec<3> tangential = Vec<3>::Zero();      // T, force on i
    Vec<3> reversal = Vec<3>::Zero();        // T*
    Vec<3> load_direction = Vec<3>::Zero();  // u of the last slip increment
    double previous_normal = 0;              // N(n-1), for step 8
    double max_overlap = 0;                  // a_max
  };
  // 2D: the tangent plane is the line along t = (-n_y, n_x), which turns with
  // the contact, so T, T* and u are their components along t and steps 2-3
  // (Eqs. 3.7-3.8) cost nothing. The same physics as the vector form, which
  // rotates each vector onto the new line keeping its length and side.
  struct History2 {
    double tangential = 0;       // T . t
    double reversal = 0;         // T* . t
    double load_direction = 0;   // u . t: +1, -1, or 0 before any slip
    double previous_normal = 0;  // N(n-1), for step 8
    double max_overlap = 0;      // a_max
  };
  template <int D>
  using History = std::conditional_t<D == 2, History2, History3>;

  template <typename H>
  static bool touching(const Params&, const H&, double overlap) {
    return overlap > 0;
  }

  // Whether rule_time_step's n counts steps of a contact time t_c (the run header
  // says it): here t_c = pi sqrt(m*/K2), the unloading spring's, and a contact
  // lasts n (1 + e)/(2e) steps.
  static constexpr bool steps_per_contact_counted = true;
  // Eq. 4.1: dt = pi e sqrt(m/(2 K_N)) / n, with m/2 the reduced mass of two equal spheres.
  static double rule_time_step(const Params& p, const PairScale& s, double steps_per_contact) {
    double e = std::sqrt(p.k_load / p.k_unload);
    return pi * e * std::sqrt(s.effective_mass / p.k_load) / steps_per_contact;
  }
  // Contact duration with force, (pi/2)(sqrt(m*/K1) + sqrt(m*/K2)).
  static double contact_duration(const Params& p, double effective_mass) {
    return 0.5 * pi *
           (std::sqrt(effective_mass / p.k_load) + std::sqrt(effective_mass / p.k_unload));
  }
  // Leap-frog is stable for dt < 2/omega; omega from the stiffer unloading spring.
  // 2 / omega of the unloading spring K2 alone (the rolling term scales this one).
  static double normal_stability_limit(const Params& p, const PairScale& s) {
    return 2.0 / std::sqrt(p.k_unload / s.effective_mass);
  }
  // 2 / omega of the stiffer of the contact's modes: K2's, and with friction the
  // tangential spring's at its stiffest, tau K2 (Eq. 3.4 on the unloading
  // branch), at omega_t^2 = 3.5 tau K2 / m* (tangential_mass_factor): the
  // default tau = 0.8 needs n > pi sqrt(2.8) = 5.26 steps per contact, where
  // frictionless contacts need n > pi.
  static double stability_limit(const Params& p, const PairScale& s) {
    const double k =
        p.friction > 0
            ? std::max(p.k_unload, tangential_mass_factor * p.tangential_ratio * p.k_unload)
            : p.k_unload;
    return 2.0 / std::sqrt(k / s.effective_mass);
  }

  // Eq. 3.4's branch for K0: on the loading line when the overlap is at a_max
  // (already raised to it) up to round-off. An overlap recomputed from moving
  // centres scatters by ~1e-16 of the centres' distance, so a contact held at a
  // constant overlap would fall below a_max on some steps and take tau K2 =
  // tau K1 / e^2 there: its tangential stiffness, and the energy a cycle of
  // tangential load dissipates, would be set by round-off (a pair's unlike a
  // wall's, whose overlap has none). The normal force is continuous across the
  // branches and needs no such margin. 1e-9 covers the round-off of overlaps
  // down to ~1e-6 of the radii.
  static bool on_loading_line(double overlap, double max_overlap) {
    return overlap >= max_overlap * (1 - 1e-9);
  }

  // Eq. 3.3 needs T* below mu N along the slip, T lying between them. Eq. 3.13
  // keeps T* / (mu N) as it was, so T* reaches mu N only when the friction
  // coefficient is lowered while the contact lasts (a schedule, set_contact), or
  // when the slip turns back the step after a reversal made in full sliding.
  // T* is then beyond what the contact can carry, and is taken as 0, as for a
  // contact loaded from rest (a slip that has gone all the way wipes the
  // memory of the reversal). Kept, it would leave no room (mu N - T* <= 0), so k_t = 0 for the
  // rest of the contact and T, capped by Eq. 3.17 whenever N falls, could never
  // grow back with N: the friction would stay at mu times the lowest N since.
  static bool forgets_reversal(double star_u, double limit) { return star_u >= limit; }

  template <int D>
  static ContactForce<D> force(const Params& p, History<D>& h, const ContactState<D>& c) {
    ContactForce<D> out;
    // Normal, Eqs. 3.1-3.2 with partial latching.
    const double a = c.overlap;
    const bool loading = a >= h.max_overlap;
    if (loading) h.max_overlap = a;
    const double permanent_set = h.max_overlap * p.permanent_set_fraction;
    double normal = loading ? p.k_load * a : p.k_unload * (a - permanent_set);
    if (normal < 0) normal = 0;
    out.normal = normal;

    // Step 4 and Eq. 3.4: initial tangential stiffness follows the normal branch.
    const double k0 =
        p.tangential_ratio * (on_loading_line(a, h.max_overlap) ? p.k_load : p.k_unload);
    const double limit = p.friction * normal;
    if (limit <= 0) {  // no friction, or N = 0 in the permanent-set gap: |T| <= mu N = 0
      if constexpr (D == 2) {
        h.tangential = h.reversal = 0;
      } else {
        h.tangential.setZero();
        h.reversal.setZero();
      }
      h.previous_normal = normal;
      return out;
    }

    if constexpr (D == 2) {
      force_2d(p, h, c, normal, k0, limit, out);
      return out;
    } else {
      // Steps 2-3 (Eqs. 3.7-3.8): carry T, T* and u onto the current tangent plane.
      Vec<D> t_force = rotate_onto_plane<D>(h.tangential, c.normal);
      Vec<D> reversal = rotate_onto_plane<D>(h.reversal, c.normal);
      Vec<D> previous_u = rotate_onto_plane<D>(h.load_direction, c.normal);

      // Step 5 (Eq. 3.10): slip increment of j's surface relative to i's.
      const Vec<D> slip = c.tangential_velocity * c.dt;

      // Step 4 (Eq. 3.9): unit vector of T; for T = 0 take the slip direction.
      const double t_mag = t_force.norm();
      Vec<D> t_hat;
      if (t_mag > 0) {
        t_hat = t_force / t_mag;
      } else {
        double s = slip.norm();
        t_hat = s > 0 ? Vec<D>(slip / s) : Vec<D>(Vec<D>::Zero());
      }
      // Steps 6-7 (Eqs. 3.11-3.12).
      const double slip_parallel = slip.dot(t_hat);
      const Vec<D> slip_par = slip_parallel * t_hat;
      const Vec<D> slip_perp = slip - slip_par;

      // Step 8 (Eq. 3.13): scale T* with the normal force; N(n-1) = 0 means a fresh contact.
      if (h.previous_normal > 0)
        reversal *= normal / h.previous_normal;
      else
        reversal.setZero();

      double k_t = k0;
      if (slip_parallel != 0) {
        const Vec<D> u = slip_parallel > 0 ? t_hat : Vec<D>(-t_hat);
        // Loading reversal: T* takes the value T had when the direction of change flipped.
        if (u.dot(previous_u) < 0) reversal = t_force;
        previous_u = u;
        // Step 9 (Eq. 3.3) read along u.
        const double t_u = t_force.dot(u);
        double star_u = reversal.dot(u);
        if (forgets_reversal(star_u, limit)) reversal.setZero(), star_u = 0;
        const double room = limit - star_u;
        double fraction = room > 0 ? 1.0 - (t_u - star_u) / room : 0.0;
        fraction = fraction < 0 ? 0 : (fraction > 1 ? 1 : fraction);
        k_t = k0 * (p.slip_exponent == 1.0 ? fraction : std::pow(fraction, p.slip_exponent));
      }
      // Steps 10-12 (Eqs. 3.14-3.16).
      Vec<D> t_new = t_force + k_t * slip_par + k0 * slip_perp;
      // Step 13 (Eq. 3.17): |T| <= mu N.
      const double new_sq = t_new.squaredNorm();
      if (new_sq > limit * limit) t_new *= limit / std::sqrt(new_sq);

      h.tangential = t_new;
      h.reversal = reversal;
      h.load_direction = previous_u;
      h.previous_normal = normal;
      out.tangential = t_new;
      return out;
    }
  }

  // The tangential steps in 2D, read along t: every vector of the general form
  // is its component along t times t, and the perpendicular slip (Eq. 3.12) is
  // zero.
  static void force_2d(const Params& p, History2& h, const ContactState<2>& c, double normal,
                       double k0, double limit, ContactForce<2>& out) {
    const Vec<2> t_axis(-c.normal.y(), c.normal.x());
    double t_force = h.tangential, reversal = h.reversal, previous_u = h.load_direction;
    const double slip = c.tangential_velocity.dot(t_axis) * c.dt;  // Eq. 3.10
    // Step 4 (Eq. 3.9): sign of T, or of the slip for T = 0.
    const double t_hat = t_force > 0   ? 1.0
                         : t_force < 0 ? -1.0
                         : slip > 0    ? 1.0
                         : slip < 0    ? -1.0
                                       : 0.0;
    const double slip_parallel = slip * t_hat;  // Eq. 3.11
    // Step 8 (Eq. 3.13).
    reversal = h.previous_normal > 0 ? reversal * (normal / h.previous_normal) : 0.0;
    double k_t = k0;
    if (slip_parallel != 0) {
      const double u = slip > 0 ? 1.0 : -1.0;  // direction of the slip increment
      if (u * previous_u < 0) reversal = t_force;
      previous_u = u;
      // Step 9 (Eq. 3.3) read along u.
      if (forgets_reversal(reversal * u, limit)) reversal = 0;
      const double t_u = t_force * u, star_u = reversal * u;
      const double room = limit - star_u;
      double fraction = room > 0 ? 1.0 - (t_u - star_u) / room : 0.0;
      fraction = fraction < 0 ? 0 : (fraction > 1 ? 1 : fraction);
      k_t = k0 * (p.slip_exponent == 1.0 ? fraction : std::pow(fraction, p.slip_exponent));
    }
    // Steps 10-13 (Eqs. 3.14-3.17); slip_parallel t_hat = slip.
    double t_new = t_force + k_t * slip;
    if (t_new > limit) t_new = limit;
    if (t_new < -limit) t_new = -limit;
    h.tangential = t_new;
    h.reversal = reversal;
    h.load_direction = previous_u;
    h.previous_normal = normal;
    out.tangential = t_new * t_axis;
  }

  // force() for batches of contacts (contact_batch.hpp; walton_braun_batch.hpp).
  struct BatchHistory2 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double tangential[lanes], reversal[lanes], load_direction[lanes];
    alignas(64) double previous_normal[lanes], max_overlap[lanes];
    void load(int l, const History2& h) {
      tangential[l] = h.tangential, reversal[l] = h.reversal;
      load_direction[l] = h.load_direction, previous_normal[l] = h.previous_normal;
      max_overlap[l] = h.max_overlap;
    }
    void store(int l, History2& h) const {
      h.tangential = tangential[l], h.reversal = reversal[l];
      h.load_direction = load_direction[l], h.previous_normal = previous_normal[l];
      h.max_overlap = max_overlap[l];
    }
    void pad(int l) {
      tangential[l] = reversal[l] = load_direction[l] = previous_normal[l] = max_overlap[l] = 0;
    }
  };
  struct BatchHistory3 {
    static constexpr int lanes = batch_lanes;
    alignas(64) double tx[lanes], ty[lanes], tz[lanes];  // T
    alignas(64) double rx[lanes], ry[lanes], rz[lanes];  // T*
    alignas(64) double ux[lanes], uy[lanes], uz[lanes];  // u
    alignas(64) double previous_normal[lanes], max_overlap[lanes];
    void load(int l, const History3& h) {
      tx[l] = h.tangential.x(), ty[l] = h.tangential.y(), tz[l] = h.tangential.z();
      rx[l] = h.reversal.x(), ry[l] = h.reversal.y(), rz[l] = h.reversal.z();
      ux[l] = h.load_direction.x(), uy[l] = h.load_direction.y(), uz[l] = h.load_direction.z();
      previous_normal[l] = h.previous_normal, max_overlap[l] = h.max_overlap;
    }
    void store(int l, History3& h) const {
      h.tangential = Vec<3>(tx[l], ty[l], tz[l]);
      h.reversal = Vec<3>(rx[l], ry[l], rz[l]);
      h.load_direction = Vec<3>(ux[l], uy[l], uz[l]);
      h.previous_normal = previous_normal[l], h.max_overlap = max_overlap[l];
    }
    void pad(int l) {
      tx[l] = ty[l] = tz[l] = rx[l] = ry[l] = rz[l] = ux[l] = uy[l] = uz[l] = 0;
      previous_normal[l] = max_overlap[l] = 0;
    }
  };
  template <bool Uniform>
  struct LaneParams;
  static void force_batch(const Params* const lane[], BatchHistory2& h, ContactBatch<2>& c);
  static void force_batch(const Params* const lane[], BatchHistory3& h, ContactBatch<3>& c);
  // The law reads no mass, so the batch never fetches the pair's masses
  // (contact_batch.hpp: batch_needs_mass).
  template <typename H>
  static bool batch_needs_mass(const H&) {
    return false;
  }
  template <typename P>
  static void force_lanes(const P& q, BatchHistory2& h, ContactBatch<2>& c);
  template <typename P>
  static void force_lanes(const P& q, BatchHistory3& h, ContactBatch<3>& c);
};

}  // namespace granule

#include "contact/walton_braun_batch.hpp"
