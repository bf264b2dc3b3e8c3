// What a contact model is told about one contact at one step, and what it
// answers. Sign conventions (used by every model and by Eq. 3.10):
//  - `normal` is the unit vector from particle j (or the wall) to particle i;
//  - the force returned is the force ON i: normal_force * normal + tangential;
//    j receives the opposite;
//  - `tangential_velocity` is the velocity of j's contact point relative to
//    i's, projected on the tangent plane (Eq. 3.10 divided by dt), so friction
//    on i points along it.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "core/material.hpp"
#include "core/types.hpp"

namespace granule {

// Whether a model reads ContactState::effective_mass / effective_radius
// (each a division per contact and step): a model says so with
// `static constexpr bool uses_effective_mass = false;` (or radius); by
// default it does. Unread fields are left NaN.
template <typename M, typename = void>
struct uses_effective_mass : std::true_type {};
template <typename M>
struct uses_effective_mass<M, std::void_t<decltype(M::uses_effective_mass)>>
    : std::bool_constant<M::uses_effective_mass> {};
template <typename M, typename = void>
struct uses_effective_radius : std::true_type {};
template <typename M>
struct uses_effective_radius<M, std::void_t<decltype(M::uses_effective_radius)>>
    : std::bool_constant<M::uses_effective_radius> {};

template <int D>
struct ContactState {
  Vec<D> normal;
  double overlap;              // m, positive when the surfaces interpenetrate
  double normal_velocity;      // m/s, rate of change of the overlap (positive: approaching)
  Vec<D> tangential_velocity;  // m/s
  double effective_mass;       // kg, m_i m_j / (m_i + m_j); m_i against a wall or fixed particle
  double inv_mass_sum;         // 1/kg, 1/m_i + 1/m_j (always set: no division)
  double effective_radius;     // m, r_i r_j / (r_i + r_j); r_i against a flat wall
  double dt;                   // s
};

// What a model may derive its parameters from, once per material pair.
struct PairMaterials {
  const Material& a;
  const Material& b;  // another particle's, or a wall's (a material may serve both)
};

// The scale of the shortest contacts a material pair can have in this scene
// (smallest particles), for the time-step rule and the stability limit.
// m* / m_t: how much lighter a contact's tangential slip is than its normal
// approach, since the slip turns the particles too. Each particle adds
// 1/m + r^2/I to 1/m_t, 3.5/m for a solid sphere (I = 2/5 m r^2, in 2D as in
// 3D: a 2D particle is a sphere moving in a plane), so a tangential spring k_t
// oscillates at omega_t^2 = 3.5 k_t / m*.
inline constexpr double tangential_mass_factor = 3.5;

struct PairScale {
  double effective_mass;    // kg
  double effective_radius;  // m (a flat wall counts as infinite)
  double rayleigh_time;     // s, Eq. 6.1 for the smallest particle; infinity if E is not given
  // E* and G* of a contact of the material that set rayleigh_time with itself
  // (Pa; 0: not known), the contact the Rayleigh limit stands for.
  double rayleigh_e_star = 0;
  double rayleigh_g_star = 0;
};

// The Hertzian laws' stability limit (before the half the engine takes): the
// Rayleigh time, which stands for a contact of the particle's material with
// itself. A Hertz impact at a given speed lasts t_c ~ E*^(-2/5) (its modes as
// much slower), so against a partner softer than the particle's own material
// (steel on rubber: E* ~1e5 times smaller) the limit is longer by
// (E*_self / E*)^(2/5), the smaller of that and the same for G*: the same
// steps per contact at any speed as the self contact at its limit. A stiffer
// partner (a rigid wall, E* up to twice the self contact's) keeps the Rayleigh
// limit, as the dissertation's rule (Eqs. 6.1-6.2) does, and the run's check
// of deep contacts watches the modes at the overlaps reached.
inline double softer_partner_limit(const PairScale& s, double e_star, double g_star) {
  if (!(s.rayleigh_e_star > 0 && s.rayleigh_g_star > 0 && e_star > 0 && g_star > 0))
    return s.rayleigh_time;
  const double softer = std::min(s.rayleigh_e_star / e_star, s.rayleigh_g_star / g_star);
  return softer > 1 ? s.rayleigh_time * std::pow(softer, 0.4) : s.rayleigh_time;
}

template <int D>
struct ContactForce {
  double normal = 0;                   // N, positive = repulsive
  Vec<D> tangential = Vec<D>::Zero();  // N, on i
};

// Steps 2-3 of Walton-Braun (Eqs. 3.7-3.8), used by every model that keeps a
// tangential vector in its history: project onto the current tangent plane,
// then restore the old magnitude so that a rotating contact does not lose force.
template <int D>
inline Vec<D> rotate_onto_plane(const Vec<D>& old, const Vec<D>& normal) {
  const double old_sq = old.squaredNorm();
  if (old_sq == 0.0) return old;
  if constexpr (D == 2) {
    // The tangent "plane" is the line along t = (-n_y, n_x): the result is |old|
    // along +t or -t, whichever side old projects to.
    const Vec<D> t(-normal.y(), normal.x());
    const double along = old.dot(t);
    if (along * along <= 1e-30 * old_sq) return Vec<D>::Zero();
    const double magnitude = std::sqrt(old_sq);
    return (along > 0 ? magnitude : -magnitude) * t;
  } else {
    const double along = normal.dot(old);
    const Vec<D> projected = old - normal * along;
    // The rescale factor is (1 - x)^-1/2 with x = along^2 / |old|^2, the
    // squared sine of the angle the normal turned through since the last step:
    // ~1e-10 in a steady contact. There the series to x^3 is exact to round-off
    // (its first omitted term, 35/128 x^4, is below 3e-17 for x < 1e-4) and
    // spares the contact a square root and a division on its critical path.
    const double x = along * along / old_sq;
    if (x < 1e-4) return projected * (1.0 + x * (0.5 + x * (0.375 + x * 0.3125)));
    const double projected_sq = projected.squaredNorm();
    if (projected_sq <= 1e-30 * old_sq) return Vec<D>::Zero();
    return projected * std::sqrt(old_sq / projected_sq);
  }
}

}  // namespace granule
