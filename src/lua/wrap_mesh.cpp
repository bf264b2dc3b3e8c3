// sim:wall_mesh: a triangle-mesh wall from a CAD file (3D).
#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "geometry/mesh_surface.hpp"
#include "io/mesh_file.hpp"
#include "lua/lua_util.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

namespace {
// rotate = { axis = { x, y, z }, degrees = a }, or { x = a, y = b, z = c }:
// degrees about the fixed x, then y, then z axes.
Eigen::Matrix3d read_rotation(lua_State* L, TableReader& outer) {
  if (!outer.push_table("rotate")) return Eigen::Matrix3d::Identity();
  TableReader t(L, lua_gettop(L), outer.context() + ".rotate");
  Eigen::Matrix3d r;
  const double to_rad = M_PI / 180;
  if (t.has("axis") || t.has("degrees")) {
    const auto a = t.vector("axis", 3);
    const double deg = t.number("degrees");
    const Eigen::Vector3d axis(a[0], a[1], a[2]);
    if (!(axis.norm() > 0) || !axis.allFinite() || !std::isfinite(deg))
      throw std::runtime_error(fmt::format(
          "{}.rotate: axis must be a finite non-zero vector and degrees finite", outer.context()));
    r = io::rotation_about(axis, deg * to_rad);
  } else {
    const double x = t.number("x", 0), y = t.number("y", 0), z = t.number("z", 0);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw std::runtime_error(fmt::format("{}.rotate: angles must be finite", outer.context()));
    r = io::rotation_xyz(x * to_rad, y * to_rad, z * to_rad);
  }
  t.finish();
  lua_pop(L, 1);
  return r;
}
}  // namespace

int l_wall_mesh(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "wall_mesh");
    MeshWallSpec w;
    w.name = t.string("name");
    if (dim(L) != 3)
      throw std::runtime_error(fmt::format(
          "wall_mesh '{}': mesh walls are for 3D scenes; in 2D, draw shapes with polyline walls "
          "(line segments and arcs)",
          w.name));
    w.file = t.string("file");
    w.material = s.sim->material_id(t.string("material"));
    io::MeshTransform place;
    place.scale = t.number("scale", 1);
    const auto shift = t.vector("translate", 3, {0, 0, 0});
    place.translation = Eigen::Vector3d(shift[0], shift[1], shift[2]);
    place.rotation = read_rotation(L, t);
    w.velocity = t.vector("velocity", 3, {0, 0, 0});
    w.angular_velocity = t.number("angular_velocity", 0);
    w.axis = t.vector("axis", 3, {0, 0, 1});
    w.axis_point = t.vector("axis_point", 3, {0, 0, 0});
    w.flat_angle = t.number("flat_angle", MeshSurface::default_flat_angle);
    t.finish();
    io::MeshFileReport report;
    Triangles mesh = io::read_mesh_file(w.file, place, report);
    w.warnings = report.warnings(w.file);
    s.sim->add_mesh_wall(w, std::move(mesh));
    return 0;
  });
}

}  // namespace granule::lua
