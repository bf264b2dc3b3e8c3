// Closest points on the finite analytic walls: a rectangle (a bounded plane; a
// segment in 2D) and the surfaces of revolution of one straight meridian
// segment about an axis (a disk or annulus, a finite cylinder, a cone or
// frustum; in 2D the segment and its mirror image across the axis).
//
// A finite wall is a thin two-sided surface: the contact is at the point of
// the bounded surface closest to the particle's centre, so its normal runs
// from that point to the centre. Inside a face this is the face normal; past
// an edge or rim it turns continuously round the edge, so a particle rolling
// over a rim feels neither a jump in the overlap nor in the normal (the
// closest-feature rule of contact elimination for triangle meshes, applied
// to a single feature, the surface).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace granule {

template <int D>
struct Nearest {
  Vec<D> point;   // the closest point of the surface
  Vec<D> normal;  // unit, from `point` to the particle's centre
  double distance = 0;
  // The radius of curvature of the surface across the contact (the
  // circumferential one of a surface of revolution; its meridian is straight),
  // 0 where it is flat; concave when the centre lies on the axis's side.
  double curvature_radius = 0;
  bool concave = false;
};

namespace finite_detail {
// A unit vector perpendicular to the unit vector a.
template <int D>
Vec<D> perpendicular(const Vec<D>& a) {
  if constexpr (D == 2) {
    return Vec<2>(-a.y(), a.x());
  } else {
    const Vec<3> helper = std::abs(a.x()) < 0.9 ? Vec<3>::UnitX() : Vec<3>::UnitY();
    return a.cross(helper).normalized();
  }
}
}  // namespace finite_detail

// The rectangle centred on `centre` with unit normal `n`, its first side along
// the unit in-plane vector `u` (half length half_a) and, in 3D, its second
// along n x u (half length half_b).
template <int D>
Nearest<D> nearest_on_rectangle(const Vec<D>& x, const Vec<D>& centre, const Vec<D>& n,
                                const Vec<D>& u, double half_a, double half_b) {
  const Vec<D> d = x - centre;
  Nearest<D> out;
  out.point = centre + u * std::clamp(d.dot(u), -half_a, half_a);
  if constexpr (D == 3) {
    const Vec<3> v = n.cross(u);
    out.point += v * std::clamp(d.dot(v), -half_b, half_b);
  }
  const Vec<D> gap = x - out.point;
  out.distance = gap.norm();
  // On the surface itself the side is the one the normal points to.
  out.normal = out.distance > 0 ? Vec<D>(gap / out.distance) : n;
  return out;
}

// The surface of revolution about the unit axis `a` through `origin` of the
// meridian segment from (rho0, z0) to (rho1, z1), where rho is the distance
// from the axis and z the coordinate along it from `origin`. Because every
// meridian half-plane holds the same segment, the closest point lies in the
// half-plane of x: a 2D closest point on a segment. In 3D the circumferential
// curvature of the surface there is |n_rho| / rho (n_rho: the radial part of
// the face normal); in 2D the mirrored segments are straight.
template <int D>
Nearest<D> nearest_on_revolved(const Vec<D>& x, const Vec<D>& origin, const Vec<D>& a, double rho0,
                               double z0, double rho1, double z1) {
  const Vec<D> d = x - origin;
  const double z = d.dot(a);
  const Vec<D> q = d - a * z;
  const double rho = q.norm();
  // On the axis every radial direction is as close: any one will do.
  const Vec<D> e = rho > 1e-300 ? Vec<D>(q / rho) : finite_detail::perpendicular<D>(a);
  const double s_rho = rho1 - rho0, s_z = z1 - z0;
  const double t =
      std::clamp(((rho - rho0) * s_rho + (z - z0) * s_z) / (s_rho * s_rho + s_z * s_z), 0.0, 1.0);
  const double c_rho = rho0 + t * s_rho, c_z = z0 + t * s_z;
  const double g_rho = rho - c_rho, g_z = z - c_z;
  Nearest<D> out;
  out.point = origin + a * c_z + e * c_rho;
  out.distance = std::hypot(g_rho, g_z);
  // The face normal in the meridian plane, turned to the centre's side.
  const double length = std::hypot(s_rho, s_z);
  double f_rho = -s_z / length, f_z = s_rho / length;
  if (g_rho * f_rho + g_z * f_z < 0) f_rho = -f_rho, f_z = -f_z;
  if (out.distance > 0) {
    out.normal = (e * g_rho + a * g_z) / out.distance;
  } else {
    out.normal = e * f_rho + a * f_z;
  }
  if constexpr (D == 3) {
    if (std::abs(f_rho) > 1e-12 && c_rho > 0) {
      out.curvature_radius = c_rho / std::abs(f_rho);
      out.concave = f_rho < 0;
    }
  }
  return out;
}

// R* of a sphere of radius r against a surface of curvature radius R (0: flat),
// the one-curvature combination the infinite cylinder uses. A concave surface
// tighter than the sphere's diameter (a cone's narrow end) is taken as R = 2r.
inline double effective_radius_against(double r, double R, bool concave) {
  if (!(R > 0)) return r;
  if (!concave) return r * R / (R + r);
  R = std::max(R, 2 * r);
  return r * R / (R - r);
}

}  // namespace granule
