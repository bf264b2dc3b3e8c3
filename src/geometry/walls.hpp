// Analytic walls. The dissertation built its cylinders out of boundary
// particles; analytic surfaces are smoother and cheaper, and carry the two
// things the physics needs (SPEC 4.1): their own material (so wall friction
// differs from particle friction) and their surface velocity at the contact
// point, which enters the slip of Eq. 3.10.
#pragma once

#include <cmath>
#include <limits>
#include <string>

#include "core/types.hpp"
#include "geometry/finite_walls.hpp"

namespace granule {

// plane and cylinder are infinite unless `bounded`; disk and cone are finite;
// mesh: a triangle mesh (3D), polyline: a chain of segments and arcs (2D);
// geometry/mesh_set.hpp and kernel/mesh_contacts.hpp measure their contacts.
enum class WallType { plane, cylinder, mesh, disk, cone, polyline };

// Whether a wall's contacts are found by the surface search (mesh_contacts.hpp)
// rather than by Wall::contact.
inline bool is_surface_wall(WallType t) {
  return t == WallType::mesh || t == WallType::polyline;
}

// The name a wall's type has in Lua (sim:wall) and in the output (/walls/<name>).
// Whether a wall of type t is finite: disks and cones always, planes and
// cylinders when bounded.
inline bool is_finite_wall(WallType t, bool bounded) {
  return bounded || t == WallType::disk || t == WallType::cone;
}

inline const char* wall_type_name(WallType t) {
  static const char* const names[] = {"plane", "cylinder", "mesh", "disk", "cone", "polyline"};
  return names[static_cast<int>(t)];
}

template <int D>
struct Wall {
  using V = Vec<D>;
  std::string name;
  WallType type = WallType::plane;
  int material = -1;
  // plane: particles live on the side `normal` points to
  V point = V::Zero();
  V normal = V::Zero();
  V velocity = V::Zero();  // m/s, translation set by the script
  // cylinder: axis through `center` along `axis` (always z in 2D)
  V center = V::Zero();
  V axis = V::Zero();
  double radius = 0;
  bool inside = true;           // particles inside the cylinder (a chamber) or outside (a post)
  double angular_velocity = 0;  // rad/s about `axis`, right-handed
  // Finite walls (finite_walls.hpp): thin two-sided surfaces, in contact at
  // their closest point. `point` is their origin (it moves with `velocity`;
  // `center` follows it) and `axis` their axis (a disk's and a rectangle's
  // normal); they turn about the axis at `angular_velocity` (3D).
  bool bounded = false;           // plane: a rectangle; cylinder: a tube between two bounds
  V side = V::Zero();             // rectangle: unit direction of its first side
  double half_a = 0, half_b = 0;  // rectangle: half the sides (half_b: 3D only)
  // disk, cone, bounded cylinder: the meridian segment from (rho0, z0) to
  // (rho1, z1), rho from the axis, z along it from `point`
  double rho0 = 0, z0 = 0, rho1 = 0, z1 = 0;
  // reaction: force and axial torque exerted BY the particles ON the wall in the last step
  V force = V::Zero();
  double axial_torque = 0;  // N m about the cylinder axis (z for planes in 2D)
  V moved_since_rebuild = V::Zero();

  bool finite() const { return is_finite_wall(type, bounded); }

  // The closest point of a finite wall to x.
  Nearest<D> nearest(const V& x) const {
    if (type == WallType::plane)
      return nearest_on_rectangle<D>(x, point, normal, side, half_a, half_b);
    return nearest_on_revolved<D>(x, point, axis, rho0, z0, rho1, z1);
  }

  // Signed clearance between the particle surface and the wall (negative: overlap).
  // Whether the wall's motion carries it along `axis`: a translation with a
  // component along it, or a turn about an axis not parallel to it.
  bool moves_along(int a) const {
    if (velocity[a] != 0) return true;
    if (angular_velocity == 0) return false;
    if constexpr (D == 3) return std::abs(std::abs(axis[a]) - 1) > 1e-12;
    return false;
  }

  double clearance(const V& x, double r) const {
    if (is_surface_wall(type)) return std::numeric_limits<double>::infinity();
    if (finite()) return nearest(x).distance - r;
    if (type == WallType::plane) return (x - point).dot(normal) - r;
    double rho = radial(x).norm();
    return inside ? radius - rho - r : rho - radius - r;
  }

  // True only where a particle at x with radius r surely does not touch an
  // unbounded cylinder: its distance from the axis checked squared, with a
  // margin far above round-off, so that contact() (a root and a division)
  // would find a negative overlap too. False for every other wall.
  bool surely_apart(const V& x, double r) const {
    if (type != WallType::cylinder || bounded) return false;
    const double rho_sq = radial(x).squaredNorm();
    if (inside) {
      const double reach = radius - r;  // touching: rho > radius - r
      return reach > 0 && rho_sq < reach * reach * (1 - 1e-9);
    }
    const double reach = radius + r;  // touching: rho < radius + r
    return rho_sq > reach * reach * (1 + 1e-9);
  }

  // The part of x - center perpendicular to the axis.
  V radial(const V& x) const {
    V d = x - center;
    if constexpr (D == 3) d -= axis * axis.dot(d);
    return d;
  }

  // Contact geometry for a particle at x with radius r. Returns the overlap;
  // fills the unit normal pointing from the wall to the particle, the wall's
  // surface velocity at the contact point and the lever arm from the axis
  // (for the reaction torque); and R* (effective_radius below) where asked, from
  // the same closest point on a finite wall.
  // Inlined into the wall loop, which calls it for every candidate.
  [[gnu::always_inline]] double contact(const V& x, double r, V& n, V& surface_velocity, V& lever,
                                        double* effective_radius_out = nullptr) const {
    if (finite()) {
      const Nearest<D> c = nearest(x);
      if (effective_radius_out)
        *effective_radius_out = effective_radius_against(r, c.curvature_radius, c.concave);
      n = c.normal;
      lever = c.point - point;
      surface_velocity = velocity;
      if constexpr (D == 3) surface_velocity += axis.cross(lever) * angular_velocity;
      return r - c.distance;
    }
    if (effective_radius_out) *effective_radius_out = effective_radius(x, r);
    if (type == WallType::plane) {
      n = normal;
      surface_velocity = velocity;
      lever = x - normal * r - point;
      return r - (x - point).dot(normal);
    }
    V d = radial(x);
    double rho = d.norm();
    V d_hat;
    if (rho > 1e-300) {
      d_hat = d / rho;
    } else {  // on the axis: any radial direction will do
      d_hat = V::Zero();
      d_hat[axis[0] != 0 && D == 3 ? 1 : 0] = 1;
      if constexpr (D == 3) d_hat = (d_hat - axis * axis.dot(d_hat)).normalized();
    }
    double overlap;
    if (inside) {
      n = -d_hat;
      overlap = rho + r - radius;
    } else {
      n = d_hat;
      overlap = radius + r - rho;
    }
    lever = d_hat * radius;
    if constexpr (D == 2) {
      surface_velocity = V(-d_hat.y(), d_hat.x()) * (angular_velocity * radius);
    } else {
      surface_velocity = axis.cross(d_hat) * (angular_velocity * radius);
    }
    return overlap;
  }

  // R* of a sphere of radius r at x touching this wall: r against a plane; against a
  // cylinder, the two curvatures combine (concave inside, convex outside); on a
  // finite wall, those of the surface at the closest point (finite_walls.hpp).
  double effective_radius(const V& x, double r) const {
    if (finite()) {
      const Nearest<D> c = nearest(x);
      return effective_radius_against(r, c.curvature_radius, c.concave);
    }
    if (type != WallType::cylinder) return r;
    return inside ? r * radius / (radius - r) : r * radius / (radius + r);
  }

  // Axial torque of a force applied at `lever` from the axis.
  double axial_moment(const V& lever, const V& f) const {
    if constexpr (D == 2) {
      return lever.x() * f.y() - lever.y() * f.x();
    } else {
      return axis.dot(lever.cross(f));
    }
  }
};

}  // namespace granule
