// sim:wall_polyline: a wall drawn in the plane as a chain of straight
// segments and circular arcs (2D).
#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "lua/lua_util.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

int l_wall_polyline(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "wall_polyline");
    PolylineWallSpec w;
    w.name = t.string("name");
    const std::string ctx = fmt::format("wall_polyline '{}'", w.name);
    if (dim(L) != 2)
      throw std::runtime_error(fmt::format(
          "{}: polyline walls are for 2D scenes; a 3D scene reads its shapes from CAD files "
          "with sim:wall_mesh",
          ctx));
    w.material = s.sim->material_id(t.string("material"));
    if (!t.push_table("points"))
      throw std::runtime_error(
          fmt::format("{}: 'points' is required: a list of {{x, y}}, at least 2", ctx));
    const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
    for (lua_Integer k = 1; k <= n; ++k) {
      lua_rawgeti(L, -1, k);
      std::array<double, 3> x{};
      try {
        x = read_vector(L, -1, 2, fmt::format("{}: points[{}]", ctx, k));
      } catch (...) {
        lua_pop(L, 2);
        throw;
      }
      lua_pop(L, 1);
      w.points.push_back({x[0], x[1]});
    }
    lua_pop(L, 1);
    w.closed = t.boolean("closed", false);
    w.solid = t.boolean("solid", false);
    if (t.push_table("arcs")) {
      const auto count = static_cast<lua_Integer>(lua_rawlen(L, -1));
      for (lua_Integer k = 1; k <= count; ++k) {
        lua_rawgeti(L, -1, k);
        PolylineWallSpec::Arc arc;
        try {
          TableReader a(L, -1, fmt::format("arcs[{}] of {}", k, ctx));
          arc.segment = a.integer("segment");
          arc.radius = a.number("radius");
          a.finish();
        } catch (...) {
          lua_pop(L, 2);
          throw;
        }
        lua_pop(L, 1);
        w.arcs.push_back(arc);
      }
      lua_pop(L, 1);
    }
    w.velocity = t.vector("velocity", 2, {0, 0, 0});
    w.angular_velocity = t.number("angular_velocity", 0);
    w.axis_point = t.vector("axis_point", 2, {0, 0, 0});
    t.finish();
    s.sim->add_polyline_wall(w);
    return 0;
  });
}

}  // namespace granule::lua
