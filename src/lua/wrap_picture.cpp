// sim:picture { file =, width =, height =, color_by =, range =, view =, walls =, legend =,
//               projection =, slab =, eye =, target = }
// Reads the options, hands them to io::write_picture (which knows nothing of Lua).
#include <fmt/format.h>

#include "io/picture.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/lua_util.hpp"

namespace granule::lua {

namespace {
// An integer option that must fit in an int (pixel counts).
int pixel_count(TableReader& t, const char* key, int fallback) {
  std::int64_t v = t.integer(key, fallback);
  if (v < 0 || v > 1'000'000)
    throw std::runtime_error(fmt::format("picture: '{}' = {} pixels is out of range", key, v));
  return static_cast<int>(v);
}
}  // namespace

int l_picture(lua_State* L) {
  return protect(L, [](lua_State* L) {
    SimulationBase& sim = simulation_argument(L);
    TableReader t(L, 2, "picture");
    io::PictureOptions o;
    o.path = t.string("file");
    o.width = pixel_count(t, "width", 800);
    o.height = pixel_count(t, "height", 0);
    o.color_by = io::parse_color_by(t.string("color_by", "speed"));
    std::vector<double> range = t.numbers("range");
    if (t.has("range")) {
      if (range.size() != 2) throw std::runtime_error("picture: range must be { min, max }");
      o.range = std::array<double, 2>{range[0], range[1]};
    }
    if (t.push_table("view")) {
      TableReader v(L, -1, "picture.view");
      auto lo = v.vector("lo", 2), hi = v.vector("hi", 2);
      v.finish();
      lua_pop(L, 1);
      o.view = std::array<double, 4>{lo[0], hi[0], lo[1], hi[1]};
    }
    o.walls = t.boolean("walls", true);
    o.legend = t.boolean("legend", true);
    o.projection = io::parse_projection(t.string("projection", "xy"));
    if (t.has("slab")) {
      std::vector<double> slab = t.numbers("slab");
      if (slab.size() != 2) throw std::runtime_error("picture: slab must be { lo, hi } [m]");
      o.slab = std::array<double, 2>{slab[0], slab[1]};
    }
    for (auto [key, where] : {std::pair{"eye", &o.eye}, std::pair{"target", &o.target}})
      if (t.has(key)) {
        auto v = t.vector(key, 3);
        *where = std::array<double, 3>{v[0], v[1], v[2]};
      }
    t.finish();
    io::write_picture(sim, o);
    lua_pushstring(L, o.path.c_str());
    return 1;
  });
}

}  // namespace granule::lua
