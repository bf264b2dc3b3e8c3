// The parallel bond of Potyondy and Cundall (2004), "A bonded-particle model
// for rock", Int. J. Rock Mech. Min. Sci. 41, 1329-1364, section 2.2: a disk
// of cement of radius R_b = lambda min(R_a, R_b) glued between two particles,
// a set of elastic springs spread over its cross-section. It carries a normal
// force, a shear force, a twisting and a bending moment, acts beside the
// pair's contact law (which goes on acting whether the bond is intact or not,
// as in PFC), and breaks for good once the largest tensile or shear stress on
// its rim reaches the cement's strength.
//
// Cross-section (Potyondy and Cundall's 3D form): A = pi R_b^2,
// I = pi R_b^4 / 4 (about a diameter), J = pi R_b^4 / 2 (polar). Granule's 2D
// particles are spheres moving in a plane (core/types.hpp: sphere mass and
// inertia in both dimensions), not disks of unit thickness, so a 2D bond keeps
// the same circular section: a 2D scene is then a slice of a 3D one in which
// nothing moves out of the plane. In 2D the spin is about z only, normal to
// every bond axis, so a 2D bond bends but never twists (M_t = 0).
//
// Loads are accumulated incrementally from the relative motion at the bond
// centre over each step (their section 2.2), all on particle a (b feels the opposite):
//   F_n += k_n A du_n        du_n = v_n dt, v_n > 0 closing (compression), v_n
//                            taken along the step's mid-chord direction (below);
//   F_s += k_s A du_s        du_s = v_s dt, v_s the velocity of b's side of the
//                            bond relative to a's in the tangent plane;
//   M_t += k_s J dtheta_n    dtheta = (w_b - w_a) dt, its part along n;
//   M_b += k_n I dtheta_s    and its part in the tangent plane.
// Potyondy and Cundall write dF_s = -k_s A dU_s with dU_s the motion of a
// relative to b: the same. Before each increment F_s (and M_b in 3D) is turned
// onto the current tangent plane keeping its length, as the contact laws'
// tangential spring is (rotate_onto_plane: the dissertation's Eqs. 3.7-3.8),
// and in 3D also turned about n by the pair's mean spin along n,
// (w_a + w_b) . n dt / 2 (PFC's second rotation): a pair spinning as one body
// about its axis carries its shear and bending with it.
// The increments are exact for a rigid motion. Leap-frog's velocities are half
// a step behind the positions (x(t) = x(t - dt) + v dt), so the closing speed is
// taken along the direction of d(t) + d(t - dt), to which the relative chord
// d(t) - d(t - dt) of a pair turning as one body is exactly normal; along the
// current normal it would read a closing speed of order Omega^2 |d| dt / 2 in a
// pair turning at Omega, and the incremental F_n would shorten the bond steadily.
// Stresses on the rim, tension positive:
//   sigma = -F_n / A + |M_b| R_b / I,   tau = |F_s| / A + |M_t| R_b / J;
// the bond breaks at the step where sigma >= tensile strength or tau >= shear
// strength, and the load of that step is not applied.
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "contact/contact_state.hpp"
#include "core/types.hpp"

namespace granule {

// What a script asks for when it bonds pairs (sim:bond): between particles of
// materials material_a and material_b (-1: any), whose surfaces are at most
// `gap` apart. Stiffnesses are per unit area (Pa/m), strengths in Pa.
struct BondSpec {
  int material_a = -1, material_b = -1;
  double gap = 0;                // m
  double radius_multiplier = 1;  // lambda of R_b = lambda min(R_a, R_b)
  double normal_stiffness = 0;   // Pa/m, k_n bar
  double shear_stiffness = 0;    // Pa/m, k_s bar
  double tensile_strength = 0;   // Pa, sigma_c
  double shear_strength = 0;     // Pa, tau_c
};

// One bond's section and cement, fixed when it is made.
struct BondProperties {
  double radius = 0;            // m, R_b
  double area = 0;              // m^2, A = pi R_b^2
  double inertia = 0;           // m^4, I = pi R_b^4 / 4
  double polar = 0;             // m^4, J = pi R_b^4 / 2
  double normal_stiffness = 0;  // Pa/m
  double shear_stiffness = 0;   // Pa/m
  double tensile_strength = 0;  // Pa
  double shear_strength = 0;    // Pa
  static constexpr int doubles = 8;
};

inline BondProperties bond_properties(double bond_radius, const BondSpec& s) {
  BondProperties b;
  const double r2 = bond_radius * bond_radius;
  b.radius = bond_radius;
  b.area = pi * r2;
  b.inertia = 0.25 * pi * r2 * r2;
  b.polar = 0.5 * pi * r2 * r2;
  b.normal_stiffness = s.normal_stiffness;
  b.shear_stiffness = s.shear_stiffness;
  b.tensile_strength = s.tensile_strength;
  b.shear_strength = s.shear_strength;
  return b;
}

// The loads a bond carries, on particle a.
template <int D>
struct BondLoad {
  double normal = 0;                      // N, F_n, compression positive (as a contact's)
  Vec<D> shear = Vec<D>::Zero();          // N, F_s, in the tangent plane
  double twist = 0;                       // N m, M_t about n (3D; 0 in 2D)
  Spin<D> bending = Dim<D>::zero_spin();  // N m, M_b (3D: in the tangent plane; 2D: about z)
  static constexpr int doubles = 1 + D + 1 + Dim<D>::spin_components;
};

// The relative motion at a bond's centre over one step.
template <int D>
struct BondMotion {
  Vec<D> normal;           // unit, from b to a (as a contact's)
  double normal_velocity;  // m/s, closing positive (along the mid-chord direction)
  Vec<D> shear_velocity;   // m/s, of b's side relative to a's, in the tangent plane
  Spin<D> relative_spin;   // rad/s, w_b - w_a
  double mean_axial_spin;  // rad/s, (w_a + w_b) . n / 2 (3D; 0 in 2D)
  double dt;               // s
};

// v turned about the unit axis n (v normal to it) by the angle `angle`.
inline Vec<3> turn_about(const Vec<3>& v, const Vec<3>& n, double angle) {
  return std::cos(angle) * v + std::sin(angle) * n.cross(v);
}

// The rim stresses (tension positive).
struct BondStress {
  double tensile = 0;  // Pa, sigma
  double shear = 0;    // Pa, tau
};

template <int D>
inline BondStress bond_stress(const BondProperties& b, const BondLoad<D>& load) {
  BondStress s;
  const double bending = std::sqrt(Dim<D>::spin_sq(load.bending));
  s.tensile = -load.normal / b.area + bending * b.radius / b.inertia;
  s.shear = load.shear.norm() / b.area + std::abs(load.twist) * b.radius / b.polar;
  return s;
}

// One step of a bond: the increments added to `load`; true when
// the bond breaks at this step (its load then stays as it was reached, for
// the record, and must not be applied).
template <int D>
inline bool advance_bond(const BondProperties& b, BondLoad<D>& load, const BondMotion<D>& m) {
  const double kn_area = b.normal_stiffness * b.area, ks_area = b.shear_stiffness * b.area;
  load.normal += kn_area * m.normal_velocity * m.dt;
  if constexpr (D == 3) {
    const double turn = m.mean_axial_spin * m.dt;
    load.shear = turn_about(rotate_onto_plane<3>(load.shear, m.normal), m.normal, turn) +
                 ks_area * m.dt * m.shear_velocity;
    const double along = m.relative_spin.dot(m.normal);
    load.twist += b.shear_stiffness * b.polar * along * m.dt;
    const Vec<3> bend = m.relative_spin - along * m.normal;
    load.bending = turn_about(rotate_onto_plane<3>(load.bending, m.normal), m.normal, turn) +
                   (b.normal_stiffness * b.inertia * m.dt) * bend;
  } else {
    load.shear = rotate_onto_plane<2>(load.shear, m.normal) + ks_area * m.dt * m.shear_velocity;
    load.bending += b.normal_stiffness * b.inertia * m.relative_spin * m.dt;
  }
  const BondStress s = bond_stress<D>(b, load);
  return s.tensile >= b.tensile_strength || s.shear >= b.shear_strength;
}

// The strain energy a bond stores (J), its springs being linear:
// F_n^2 / (2 k_n A) + |F_s|^2 / (2 k_s A) + M_t^2 / (2 k_s J) + |M_b|^2 / (2 k_n I).
template <int D>
inline double bond_energy(const BondProperties& b, const BondLoad<D>& load) {
  const double kn_area = b.normal_stiffness * b.area, ks_area = b.shear_stiffness * b.area;
  return 0.5 * (load.normal * load.normal / kn_area + load.shear.squaredNorm() / ks_area +
                load.twist * load.twist / (b.shear_stiffness * b.polar) +
                Dim<D>::spin_sq(load.bending) / (b.normal_stiffness * b.inertia));
}

// The bonds of a scene, in the order they were made (the order their loads
// are added to the particles, whatever the thread count). Particles are named
// by persistent id, so re-sorting or removing particles never confuses them.
template <int D>
struct ParallelBonds {
  std::vector<std::int64_t> id_a, id_b;  // id_a < id_b
  std::vector<BondProperties> properties;
  std::vector<BondLoad<D>> load;
  std::vector<std::uint8_t> broken;  // 1 from the step it broke (or a particle was removed)
  std::int64_t intact = 0;

  std::size_t size() const { return id_a.size(); }
  bool empty() const { return id_a.empty(); }
  void add(std::int64_t a, std::int64_t b, const BondProperties& p) {
    id_a.push_back(a), id_b.push_back(b);
    properties.push_back(p);
    load.push_back({});
    broken.push_back(0);
    ++intact;
  }
  void break_bond(std::size_t k) {
    if (broken[k]) return;
    broken[k] = 1;
    --intact;
  }
  // Calls f(k) for each bond of particle `id`, broken or not, in increasing k:
  // what a per-particle call (a move, a removal) touches, without a scan of every
  // bond. The index is made on the first call after bonds were added.
  template <typename F>
  void for_each_of(std::int64_t id, F f) const {
    if (indexed_ != size()) {
      of_particle_.clear();
      for (std::size_t k = 0; k < size(); ++k) {
        of_particle_[id_a[k]].push_back(k);
        of_particle_[id_b[k]].push_back(k);
      }
      indexed_ = size();
    }
    const auto it = of_particle_.find(id);
    if (it != of_particle_.end())
      for (const std::size_t k : it->second) f(k);
  }

 private:
  mutable std::unordered_map<std::int64_t, std::vector<std::size_t>> of_particle_;
  mutable std::size_t indexed_ = 0;  // the bonds of_particle_ holds (bonds are only appended)
};

}  // namespace granule
