// Where a picture's particles and walls go: the orthographic projections of a
// 3D scene (rotations, so that the layout, which looks along -z, draws every
// view) with an optional slab, and a pinhole camera with depth shading.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "io/picture.hpp"
#include "io/picture_draw.hpp"

namespace granule::io {

namespace {

using M3 = std::array<std::array<double, 3>, 3>;

// Rows: the picture's right, up and towards-the-viewer directions (a rotation,
// so that the layout below, which looks along -z, draws every view).
M3 view_matrix(Projection p) {
  switch (p) {
    case Projection::xz:  // looking along +y: x right, z up
      return {{{1, 0, 0}, {0, 0, 1}, {0, -1, 0}}};
    case Projection::yz:  // looking along -x: y right, z up
      return {{{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}};
    default:
      return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  }
}

Triple times(const M3& m, const Triple& v) {
  Triple out{};
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
  return out;
}

}  // namespace

namespace picture_detail {

const char* projection_name(Projection p) {
  switch (p) {
    case Projection::xy:
      return "xy";
    case Projection::xz:
      return "xz";
    case Projection::yz:
      return "yz";
    case Projection::perspective:
      return "perspective";
  }
  return "?";
}

// The axis a projection looks along, for `slab`: z, y or x.
int viewing_axis(Projection p) {
  return p == Projection::xz ? 1 : p == Projection::yz ? 0 : 2;
}

Projected project(const SimulationBase::FlatState& s, int d, const PictureOptions& o) {
  const std::size_t n = s.id.size();
  const bool perspective = o.projection == Projection::perspective;
  Projected out;
  out.position.assign(3 * n, 0.0);
  out.radius = s.radius;
  out.shade.assign(n, 1.0);
  out.shown.assign(n, 1);
  std::vector<double>& pos = out.position;
  std::vector<double>& drawn_radius = out.radius;
  std::vector<double>& shade = out.shade;
  std::vector<char>& shown = out.shown;
  auto position3 = [&](std::size_t i) {
    Triple x{s.position[i * d], s.position[i * d + 1], d == 3 ? s.position[i * d + 2] : 0.0};
    return x;
  };
  if (!perspective) {
    const M3 m = view_matrix(o.projection);
    const int along = viewing_axis(o.projection);
    for (std::size_t i = 0; i < n; ++i) {
      const Triple x = position3(i);
      const Triple v = times(m, x);
      pos[3 * i] = v[0], pos[3 * i + 1] = v[1], pos[3 * i + 2] = v[2];
      if (o.slab && !(x[along] >= (*o.slab)[0] && x[along] <= (*o.slab)[1])) shown[i] = 0;
    }
  } else {
    // A pinhole camera at `eye` looking at `target`, z up (or y when looking along z).
    Triple lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (std::size_t i = 0; i < n; ++i) {
      const Triple x = position3(i);
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], x[k] - s.radius[i]), hi[k] = std::max(hi[k], x[k] + s.radius[i]);
    }
    if (n == 0) lo = {-1e-3, -1e-3, -1e-3}, hi = {1e-3, 1e-3, 1e-3};
    Triple centre{}, eye{};
    double extent = 0;
    for (int k = 0; k < 3; ++k) {
      centre[k] = 0.5 * (lo[k] + hi[k]);
      extent = std::max(extent, hi[k] - lo[k]);
    }
    if (o.target) centre = *o.target;
    if (o.eye) {
      eye = *o.eye;
    } else {
      const double away = 2.5 * std::max(extent, 1e-9) / std::sqrt(1 + 2.25 + 0.64);
      eye = {centre[0] + 1.0 * away, centre[1] - 1.5 * away, centre[2] + 0.8 * away};
    }
    Triple forward{centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]};
    const double distance = std::hypot(forward[0], forward[1], forward[2]);
    if (!(distance > 0) || !std::isfinite(distance))
      throw InputError("picture: eye and target must be two different finite points");
    for (double& c : forward) c /= distance;
    Triple up{0, 0, 1};
    if (std::abs(forward[2]) > 0.99) up = {0, 1, 0};
    Triple right{forward[1] * up[2] - forward[2] * up[1], forward[2] * up[0] - forward[0] * up[2],
                 forward[0] * up[1] - forward[1] * up[0]};
    const double rn = std::hypot(right[0], right[1], right[2]);
    for (double& c : right) c /= rn;
    up = {right[1] * forward[2] - right[2] * forward[1],
          right[2] * forward[0] - right[0] * forward[2],
          right[0] * forward[1] - right[1] * forward[0]};
    double near = 1e300, far = -1e300;
    std::vector<double> depth(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const Triple x = position3(i);
      const Triple rel{x[0] - eye[0], x[1] - eye[1], x[2] - eye[2]};
      const double zc = rel[0] * forward[0] + rel[1] * forward[1] + rel[2] * forward[2];
      depth[i] = zc;
      if (zc <= s.radius[i]) {  // behind the camera, or around it
        shown[i] = 0;
        continue;
      }
      const double f = distance / zc;
      pos[3 * i] = f * (rel[0] * right[0] + rel[1] * right[1] + rel[2] * right[2]);
      pos[3 * i + 1] = f * (rel[0] * up[0] + rel[1] * up[1] + rel[2] * up[2]);
      pos[3 * i + 2] = -zc;  // nearer: drawn later
      drawn_radius[i] = f * s.radius[i];
      near = std::min(near, zc), far = std::max(far, zc);
    }
    // Depth shading: the farthest particles at 55 % of their colour.
    for (std::size_t i = 0; i < n; ++i)
      if (shown[i] && far > near) shade[i] = 1.0 - 0.45 * (depth[i] - near) / (far - near);
  }
  return out;
}

std::vector<WallSpec> walls_in_view(const SimulationBase& sim, const PictureOptions& o) {
  std::vector<WallSpec> walls;
  if (!o.walls || o.projection == Projection::perspective) return walls;
  const M3 m = view_matrix(o.projection);
  for (int w = 0; w < sim.wall_count(); ++w) {
    WallSpec spec = sim.wall(w);
    spec.point = times(m, spec.point), spec.normal = times(m, spec.normal);
    spec.center = times(m, spec.center), spec.axis = times(m, spec.axis);
    spec.side = times(m, spec.side);  // a rectangle's first side
    walls.push_back(spec);
  }
  return walls;
}

std::vector<MeshView> mesh_views_in_view(const SimulationBase& sim, const PictureOptions& o) {
  if (!o.walls || o.projection == Projection::perspective) return {};
  std::vector<MeshView> meshes = sim.mesh_views();
  const M3 m = view_matrix(o.projection);
  for (auto& mesh : meshes)
    for (auto& v : mesh.vertices) v = times(m, v);
  return meshes;
}

}  // namespace picture_detail

Projection parse_projection(const std::string& name) {
  for (Projection p : {Projection::xy, Projection::xz, Projection::yz, Projection::perspective})
    if (name == picture_detail::projection_name(p)) return p;
  throw InputError(
      fmt::format("picture: projection = '{}' is not one of xy, xz, yz, perspective", name));
}

}  // namespace granule::io
