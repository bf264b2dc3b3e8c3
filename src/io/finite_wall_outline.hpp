// A finite wall (geometry/finite_walls.hpp) as line segments in the x-y plane,
// for sim:picture: in 2D the wall itself (a rectangle's segment, a disk's or
// cone's two mirrored segments); in 3D, seen along z, a rectangle's four
// edges, and a disk's, tube's or cone's two rim circles with four of its
// meridian lines, all projected onto x-y.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "engine/simulation_base.hpp"

namespace granule::io {

inline std::vector<std::array<double, 4>> finite_wall_outline(const WallSpec& w, int dimension) {
  using V3 = std::array<double, 3>;
  auto add = [](const V3& a, const V3& b, double s) {
    return V3{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
  };
  auto unit = [](const V3& a) {
    const double n = std::hypot(a[0], a[1], a[2]);
    return n > 0 ? V3{a[0] / n, a[1] / n, a[2] / n} : V3{1, 0, 0};
  };
  auto cross = [](const V3& a, const V3& b) {
    return V3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  std::vector<std::array<double, 4>> out;
  auto line = [&](const V3& p, const V3& q) { out.push_back({p[0], p[1], q[0], q[1]}); };
  if (w.type == WallType::plane) {
    const V3 u = unit(w.side);
    if (dimension == 2) {
      line(add(w.point, u, -w.size_a / 2), add(w.point, u, w.size_a / 2));
      return out;
    }
    const V3 v = cross(unit(w.normal), u);
    V3 c[4];
    int k = 0;
    for (auto [a, b] : {std::array<double, 2>{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      c[k++] = add(add(w.point, u, a * w.size_a / 2), v, b * w.size_b / 2);
    for (k = 0; k < 4; ++k) line(c[k], c[(k + 1) % 4]);
    return out;
  }
  const V3 axis = unit(w.type == WallType::disk ? w.normal : w.axis);
  const double rho[2] = {w.type == WallType::disk ? w.inner_radius : w.radius_lo,
                         w.type == WallType::disk ? w.radius : w.radius_hi};
  const double z[2] = {w.z_lo, w.z_hi};
  const V3 ends[2] = {add(w.center, axis, z[0]), add(w.center, axis, z[1])};
  if (dimension == 2) {
    const V3 e{-axis[1], axis[0], 0};
    for (double side : {-1.0, 1.0})
      line(add(ends[0], e, side * rho[0]), add(ends[1], e, side * rho[1]));
    return out;
  }
  const V3 helper = std::abs(axis[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  const V3 t1 = unit(cross(axis, helper)), t2 = cross(axis, t1);
  constexpr int m = 48;
  auto at = [&](int end, double a) {
    return add(add(ends[end], t1, rho[end] * std::cos(a)), t2, rho[end] * std::sin(a));
  };
  const double step = 2 * 3.14159265358979323846 / m;
  for (int end = 0; end < 2; ++end)
    if (rho[end] > 0)
      for (int k = 0; k < m; ++k) line(at(end, k * step), at(end, (k + 1) * step));
  for (int k = 0; k < 4; ++k) line(at(0, k * m / 4 * step), at(1, k * m / 4 * step));
  return out;
}

}  // namespace granule::io
