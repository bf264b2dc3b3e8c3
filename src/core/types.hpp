// Dimension traits: the one place where 2D and 3D differ.
//
// "2D" follows the dissertation (SPEC section 2): particles are spheres whose
// centres move in the x-y plane and spin only about z. Positions are
// Eigen 2-vectors and spin is a scalar, so a 2D scene never pays for a third
// component. Everything else is written once as a template over D.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <cmath>
#include <cstdint>

namespace granule {

template <int D>
struct Dim;

template <>
struct Dim<2> {
  using Vec = Eigen::Vector2d;
  using Spin = double;  // angular velocity about z, rad/s
  static constexpr int spin_components = 1;
  static Spin zero_spin() { return 0.0; }
  // w x r for a spin about z.
  static Vec spin_cross(Spin w, const Vec& r) { return Vec(-w * r.y(), w * r.x()); }
  // r x F: the z component, the only one a planar force produces.
  static Spin torque(const Vec& r, const Vec& f) { return r.x() * f.y() - r.y() * f.x(); }
  static double spin_sq(Spin w) { return w * w; }
};

template <>
struct Dim<3> {
  using Vec = Eigen::Vector3d;
  using Spin = Eigen::Vector3d;
  static constexpr int spin_components = 3;
  static Spin zero_spin() { return Spin::Zero(); }
  static Vec spin_cross(const Spin& w, const Vec& r) { return w.cross(r); }
  static Spin torque(const Vec& r, const Vec& f) { return r.cross(f); }
  static double spin_sq(const Spin& w) { return w.squaredNorm(); }
};

template <int D>
using Vec = typename Dim<D>::Vec;
template <int D>
using Spin = typename Dim<D>::Spin;

constexpr double pi = 3.14159265358979323846;

// Sphere mass and moment of inertia, Eq. 4.7's m = pi d^3 rho / 6 and I = m d^2 / 10,
// used in both dimensions ("particles are spheres even in 2D").
inline double sphere_mass(double radius, double density) {
  return 4.0 / 3.0 * pi * radius * radius * radius * density;
}
inline double sphere_inertia(double mass, double radius) {
  return 0.4 * mass * radius * radius;
}

}  // namespace granule
