// The simulation's set-up methods: materials, contact laws, walls, particles (one by
// one or by fill), body fields, and the run-time setters of walls and particles.
#include <fmt/format.h>

#include "contact/rolling.hpp"
#include "core/errors.hpp"
#include "core/names.hpp"
#include "engine/simulation_base.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

// ---- set-up ----
int l_material(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "material");
    Material m;
    m.name = t.string("name");
    t = TableReader(L, 2, fmt::format("material '{}'", m.name));
    t.mark("name");
    m.density = t.number("density", 0);
    m.young = t.number("young", 0);
    m.poisson = t.number("poisson", 0);
    m.surface_energy = t.number("surface_energy", 0);
    t.finish();
    s.sim->add_material(m);
    lua_pushstring(L, m.name.c_str());
    return 1;
  });
}

// contact { "a", "b", model = "walton_braun", k_load = ..., ... }
int l_contact(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (!lua_istable(L, 2))
      throw std::runtime_error("contact: expected { 'a', 'b', model = ..., ... }");
    if (has_index_metamethod(L, 2))
      throw std::runtime_error("contact: expected a plain table { 'a', 'b', model = ..., ... }");
    lua_rawgeti(L, 2, 1);
    lua_rawgeti(L, 2, 2);
    if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING)
      throw std::runtime_error("contact: the first two entries must be material names");
    std::string a = lua_tostring(L, -2), b = lua_tostring(L, -1);
    lua_pop(L, 2);
    TableReader t(L, 2, fmt::format("contact '{}'-'{}'", a, b));
    std::string model = t.string("model");
    ParamValues values;
    for (const auto& key : t.keys()) {
      if (key == "model") continue;
      if (key == "rolling_model")  // a name ("epsd", "constant"): rolling.hpp
        values[key] = rolling_model_code(t.string("rolling_model"), t.context());
      else
        values[key] = t.number(key.c_str());
    }
    // The caller's file:line, for the message that a second declaration gets.
    push_script_where(L);  // "file:line: "
    std::string where = lua_tostring(L, -1);
    lua_pop(L, 1);
    while (!where.empty() && (where.back() == ' ' || where.back() == ':')) where.pop_back();
    if (where.empty()) where = "?";
    s.sim->declare_contact(a, b, model, values, where);
    return 0;
  });
}

bool replaying(lua_State* L) {
  const SceneContext* ctx = context(L);
  return ctx && ctx->journal && ctx->journal->replaying();
}

// set_contact("a", "b", { friction = 0.25 }): change parameters during a run.

int l_set_contact(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::string a = read_string(L, 2, "set_contact: first material");
    std::string b = read_string(L, 3, "set_contact: second material");
    TableReader t(L, 4, fmt::format("set_contact '{}'-'{}'", a, b));
    ParamValues values;
    if (t.has("model"))
      throw InputError(fmt::format(
          "set_contact '{}'-'{}': a pair's model is set once, by sim:contact (its contacts hold "
          "that model's histories); set_contact changes the model's parameters",
          a, b));
    // A restart's replay executes what the first run did, which passed this check
    // at its own time (the replay's engine is not at that time).
    if (!replaying(L))
      for (const auto& key : t.keys()) s.sim->claim_scheduled_contact(a, b, key);
    for (const auto& key : t.keys())
      values[key] = key == "rolling_model"
                        ? rolling_model_code(t.string("rolling_model"), t.context())
                        : t.number(key.c_str());
    s.sim->update_contact(a, b, values);
    return 0;
  });
}

int l_wall_plane(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    TableReader t(L, 2, "wall_plane");
    WallSpec w;
    w.type = WallType::plane;
    w.name = t.string("name");
    w.material = s.sim->material_id(t.string("material"));
    w.point = t.vector("point", d);
    w.normal = t.vector("normal", d);
    w.velocity = t.vector("velocity", d, {0, 0, 0});
    // A rectangle centred on `point` (a segment in 2D): size = length in 2D,
    // { a, b } in 3D, the side of length a along `side`.
    if (t.has("size")) {
      w.bounded = true;
      if (d == 2) {
        w.size_a = t.number("size");
      } else {
        const std::vector<double> size = t.numbers("size");
        if (size.size() != 2)
          throw InputError(fmt::format(
              "wall_plane: size must be {{a, b}} (the rectangle's sides, m) in 3D, got {} numbers",
              size.size()));
        w.size_a = size[0], w.size_b = size[1];
        w.side = t.vector("side", 3, {0, 0, 0});
      }
    }
    if (t.has("side") && !w.bounded) {
      t.mark("side");
      throw InputError("wall_plane: 'side' orients a bounded plane; give 'size' with it");
    }
    if (t.has("side") && d == 2) {
      t.mark("side");
      throw InputError(
          "wall_plane: in 2D a bounded plane is a segment across its normal; leave "
          "'side' out");
    }
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

namespace {
// bounds = { lo, hi }: the axial extent of a finite wall from its center [m].
void read_bounds(TableReader& t, WallSpec& w, const char* fn) {
  const std::vector<double> b = t.numbers("bounds");
  if (b.size() != 2)
    throw InputError(
        fmt::format("{}: bounds must be {{lo, hi}} (m along the axis from center), got {} numbers",
                    fn, b.size()));
  w.z_lo = b[0], w.z_hi = b[1];
}
}  // namespace

int l_wall_cylinder(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    TableReader t(L, 2, "wall_cylinder");
    WallSpec w;
    w.type = WallType::cylinder;
    w.name = t.string("name");
    w.material = s.sim->material_id(t.string("material"));
    w.center = t.vector("center", d);
    if (d == 3) {
      w.axis = t.vector("axis", 3, {0, 0, 1});
    } else if (t.has("axis")) {
      t.mark("axis");
      throw std::runtime_error("wall_cylinder: in 2D the axis is z; leave 'axis' out");
    }
    w.radius = t.number("radius");
    w.inside = t.boolean("inside", true);
    w.angular_velocity = t.number("angular_velocity", 0);
    if (t.has("bounds")) {
      if (d == 2) {
        t.mark("bounds");
        throw InputError(
            "wall_cylinder: in 2D a cylinder is a circle about z and has no "
            "bounds; draw a channel with bounded planes");
      }
      w.bounded = true;
      read_bounds(t, w, "wall_cylinder");
      w.velocity = t.vector("velocity", d, {0, 0, 0});
    } else if (t.has("velocity")) {
      t.mark("velocity");
      throw InputError(
          d == 2 ? "wall_cylinder: a circle does not translate; a closed polyline of arcs "
                   "(sim:wall_polyline with arcs) is a circle that does"
                 : "wall_cylinder: an infinite cylinder does not translate; give 'bounds' "
                   "for a finite one, which may translate");
    }
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

int l_wall_disk(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    TableReader t(L, 2, "wall_disk");
    WallSpec w;
    w.type = WallType::disk;
    w.name = t.string("name");
    w.material = s.sim->material_id(t.string("material"));
    w.center = t.vector("center", d);
    w.normal = t.vector("normal", d);
    w.radius = t.number("radius");
    w.inner_radius = t.number("inner_radius", 0);
    w.velocity = t.vector("velocity", d, {0, 0, 0});
    w.angular_velocity = t.number("angular_velocity", 0);
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

int l_wall_cone(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    TableReader t(L, 2, "wall_cone");
    WallSpec w;
    w.type = WallType::cone;
    w.name = t.string("name");
    w.material = s.sim->material_id(t.string("material"));
    w.center = t.vector("center", d);
    w.axis = t.vector("axis", d);
    read_bounds(t, w, "wall_cone");
    const std::vector<double> radii = t.numbers("radii");
    if (radii.size() != 2)
      throw InputError(fmt::format(
          "wall_cone: radii must be {{r_lo, r_hi}} (m, at the two bounds), got {} numbers",
          radii.size()));
    w.radius_lo = radii[0], w.radius_hi = radii[1];
    w.velocity = t.vector("velocity", d, {0, 0, 0});
    w.angular_velocity = t.number("angular_velocity", 0);
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

namespace {
ParticleSpec read_particle(lua_State* L, int index, SimulationBase& sim, const std::string& ctx) {
  int d = sim.dimension();
  TableReader t(L, index, ctx);
  ParticleSpec p;
  p.position = t.vector("position", d);
  p.velocity = t.vector("velocity", d, {0, 0, 0});
  if (d == 2) {
    p.spin = {0, 0, t.number("spin", 0)};
  } else {
    p.spin = t.vector("spin", 3, {0, 0, 0});
  }
  p.radius = t.number("radius");
  p.material = sim.material_id(t.string("material"));
  p.fixed = t.boolean("fixed", false);
  t.finish();
  return p;
}
}  // namespace

int l_add_particle(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    ParticleSpec p = read_particle(L, 2, *s.sim, "add_particle");
    lua_pushinteger(L, s.sim->add_particle(p));
    return 1;
  });
}

// fill { region = { circle = { center = {x, y}, radius = R } | box = { lo =, hi = } |
//        sphere = {...} | cylinder = { center =, radius =, z_min =, z_max = } },
//        count =, radius = | radii = {...} | radius_min =, radius_max =,
//        material =, seed =, max_speed = }
int l_fill(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    TableReader t(L, 2, "fill");
    FillSpec f;
    f.count = t.integer("count");
    f.material = s.sim->material_id(t.string("material"));
    f.seed = static_cast<std::uint64_t>(t.integer("seed", 1));
    f.max_speed = t.number("max_speed", 0);
    f.max_attempts = t.integer("max_attempts", 0);
    if (t.has("max_attempts") && f.max_attempts < 1)
      throw InputError(
          fmt::format("fill: max_attempts must be >= 1 (placement tries), got {}", f.max_attempts));
    f.allow_overlap = t.boolean("overlap", true);
    const int size_rules = int(t.has("radius")) + int(t.has("radii")) +
                           int(t.has("radius_min") || t.has("radius_max"));
    if (size_rules > 1)
      throw std::runtime_error(
          "fill: give one of radius, radii, or radius_min with radius_max [m]");
    // A count beyond this is no scene memory can hold, and 2000 * count attempts must not
    // overflow the engine's counter.
    if (f.count > 1'000'000'000)
      throw std::runtime_error(fmt::format("fill: count = {} is more than 1e9 particles", f.count));
    if (t.has("radius")) {
      f.radius_min = f.radius_max = t.number("radius");
    } else if (t.has("radii")) {
      f.radii = t.numbers("radii");
    } else {
      f.radius_min = t.number("radius_min");
      f.radius_max = t.number("radius_max");
    }
    if (!t.push_table("region")) throw std::runtime_error("fill: 'region' is required");
    int region = lua_gettop(L);
    TableReader r(L, region, "fill.region");
    auto shape_table = [&](const char* key) {
      if (!r.push_table(key)) return false;
      return true;
    };
    if (shape_table(d == 2 ? "circle" : "sphere")) {
      TableReader c(L, -1, d == 2 ? "fill.region.circle" : "fill.region.sphere");
      f.shape = RegionShape::ball;
      f.center = c.vector("center", d);
      f.radius = c.number("radius");
      c.finish();
      lua_pop(L, 1);
    } else if (shape_table("box")) {
      TableReader c(L, -1, "fill.region.box");
      f.shape = RegionShape::box;
      f.lo = c.vector("lo", d);
      f.hi = c.vector("hi", d);
      c.finish();
      lua_pop(L, 1);
    } else if (d == 3 && shape_table("cylinder")) {
      TableReader c(L, -1, "fill.region.cylinder");
      f.shape = RegionShape::cylinder;
      f.center = c.vector("center", 3);
      f.radius = c.number("radius");
      f.z_min = c.number("z_min");
      f.z_max = c.number("z_max");
      c.finish();
      lua_pop(L, 1);
    } else {
      // A misspelt shape ('circel') is named with the nearest shape; anything else (an
      // empty region, a sphere in 2D) gets the list.
      const std::vector<std::string> shapes =
          d == 2 ? std::vector<std::string>{"circle", "box"}
                 : std::vector<std::string>{"sphere", "box", "cylinder"};
      for (const auto& key : r.keys())
        if (std::string hint = nearest_name(key, shapes); !hint.empty())
          throw InputError(
              fmt::format("fill.region: unknown key '{}' (did you mean '{}'?)", key, hint));
      throw std::runtime_error(fmt::format("fill.region: give one of {}",
                                           d == 2 ? "circle, box" : "sphere, box, cylinder"));
    }
    r.finish();
    lua_pop(L, 1);
    t.finish();
    // A signal stops a long fill as it stops a run (no Lua runs meanwhile to see it).
    f.stop_requested = [] { return interrupt_pending(); };
    std::vector<std::int64_t> ids = s.sim->fill(f);
    if (interrupt_pending()) {
      std::string message =
          static_cast<std::int64_t>(ids.size()) < f.count
              ? fmt::format("interrupted ({}) during fill: none of its {} particles added",
                            interrupt_cause(), f.count)
              : fmt::format("interrupted ({}) as fill ended, its {} particles added",
                            interrupt_cause(), f.count);
      if (SceneContext* ctx = context(L)) ctx->interrupted = true, ctx->interrupt_message = message;
      throw std::runtime_error(message);
    }
    lua_createtable(L, static_cast<int>(ids.size()), 0);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      lua_pushinteger(L, ids[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

int l_gravity(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    s.sim->set_gravity(read_vector(L, 2, dim(L), "gravity"));
    return 0;
  });
}

// sim:set_damping { viscous =, spin =, local_fraction = } sets all three (those
// not given 0: {} is off); sim:damping() gives them.
int l_set_damping(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "set_damping");
    Damping d;
    d.viscous = t.number("viscous", 0.0);
    d.spin = t.number("spin", 0.0);
    d.local_fraction = t.number("local_fraction", 0.0);
    t.finish();
    s.sim->set_damping(d);
    return 0;
  });
}

int l_damping(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const Damping& d = self(L).sim->damping();
    lua_createtable(L, 0, 3);
    lua_pushnumber(L, d.viscous);
    lua_setfield(L, -2, "viscous");
    lua_pushnumber(L, d.spin);
    lua_setfield(L, -2, "spin");
    lua_pushnumber(L, d.local_fraction);
    lua_setfield(L, -2, "local_fraction");
    return 1;
  });
}

int l_central_field(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "central_field");
    auto point = t.vector("point", dim(L));
    double strength = t.number("strength");
    t.finish();
    if (!replaying(L)) s.sim->claim_scheduled_field("central_field");
    s.sim->set_central_field(point, strength);
    return 0;
  });
}

int l_set_central_strength(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    const double strength = read_number(L, 2, "central field strength");
    if (!replaying(L)) s.sim->claim_scheduled_field("set_central_strength");
    s.sim->set_central_strength(strength);
    return 0;
  });
}

int l_central_strength(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushnumber(L, self(L).sim->central_strength());
    return 1;
  });
}

int l_remove_central_field(lua_State* L) {
  return protect(L, [](lua_State* L) {
    self(L).sim->clear_central_field();
    return 0;
  });
}

// ---- walls at run time ----
int l_set_wall(lua_State* L) {
  return protect(L, [](lua_State* L) {
    // A wall's velocities: every rank of a spread scene holds the walls and
    // sets them alike, so the shares are kept (a shaken floor set every step).
    LuaSim& s = self_kept(L);
    int w = s.sim->wall_id(read_string(L, 2, "set_wall: wall name"));
    TableReader t(L, 3, "set_wall");
    for (const char* key : {"velocity", "angular_velocity"})
      if (t.has(key) && !replaying(L)) s.sim->claim_scheduled_wall(w, key);
    if (t.has("velocity")) s.sim->set_wall_velocity(w, t.vector("velocity", dim(L)));
    if (t.has("angular_velocity"))
      s.sim->set_wall_angular_velocity(w, t.number("angular_velocity"));
    t.finish();
    return 0;
  });
}

int l_set_velocity(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    s.sim->set_velocity(id, read_vector(L, 3, dim(L), "velocity"));
    return 0;
  });
}
int l_set_position(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    s.sim->set_position(id, read_vector(L, 3, dim(L), "position"));
    return 0;
  });
}
int l_set_fixed(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    if (lua_type(L, 3) != LUA_TBOOLEAN)
      throw InputError(
          fmt::format("set_fixed: argument 2 must be true or false, got {}", luaL_typename(L, 3)));
    s.sim->set_fixed(id, lua_toboolean(L, 3) != 0);
    return 0;
  });
}
int l_set_spin(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    if (dim(L) == 2)
      s.sim->set_spin(id, {0, 0, read_number(L, 3, "spin")});
    else
      s.sim->set_spin(id, read_vector(L, 3, 3, "spin"));
    return 0;
  });
}
int l_remove_particle(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    s.sim->remove_particle(particle_id(L, 2, *s.sim));
    return 0;
  });
}

}  // namespace granule::lua
