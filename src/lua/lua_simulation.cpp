// simulation { ... } and the methods of a Simulation userdata. Bindings only:
// each method reads its arguments, calls SimulationBase, pushes results.
#include "lua/lua_simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "core/errors.hpp"
#include "engine/run_loop.hpp"
#include "engine/simulation_base.hpp"
#include "io/run_output.hpp"
#include "lua/api_docs.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/run_progress.hpp"
#include "lua/scene.hpp"
#include "lua/wrap_agglomerate.hpp"

namespace granule::lua {

LuaSim& self(lua_State* L) {
  void* p = luaL_testudata(L, 1, simulation_metatable);
  if (!p) throw std::runtime_error("expected a simulation: call methods as sim:method(...)");
  auto* s = static_cast<LuaSim*>(p);
  if (!s->sim) throw std::runtime_error("this simulation has been closed");
  return *s;
}

namespace {
const char* metatable_name = simulation_metatable;
// The list of simulations made in this state, for simulations() and the REPL.
const char* simulations_key = "granule.simulations";

int dim(lua_State* L) {
  return self(L).sim->dimension();
}

// A method defined in a wrap_*.cpp file, given the checked simulation.
template <int (*Method)(lua_State*, SimulationBase&)>
int bound(lua_State* L) {
  return protect(L, [](lua_State* L) { return Method(L, *self(L).sim); });
}

std::int64_t particle_id(lua_State* L, int index, const SimulationBase& sim) {
  std::int64_t id = read_integer(L, index, "particle id");
  if (!sim.has_particle(id)) throw InputError(fmt::format("no particle with id {}", id));
  return id;
}

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
    lua_geti(L, 2, 1);
    lua_geti(L, 2, 2);
    if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING)
      throw std::runtime_error("contact: the first two entries must be material names");
    std::string a = lua_tostring(L, -2), b = lua_tostring(L, -1);
    lua_pop(L, 2);
    TableReader t(L, 2, fmt::format("contact '{}'-'{}'", a, b));
    std::string model = t.string("model");
    ParamValues values;
    for (const auto& key : t.keys()) {
      if (key == "model") continue;
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

// set_contact("a", "b", { friction = 0.25 }): change parameters during a run.
int l_set_contact(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::string a = read_string(L, 2, "set_contact: first material");
    std::string b = read_string(L, 3, "set_contact: second material");
    TableReader t(L, 4, fmt::format("set_contact '{}'-'{}'", a, b));
    ParamValues values;
    for (const auto& key : t.keys()) values[key] = t.number(key.c_str());
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
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

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
    t.finish();
    s.sim->add_wall(w);
    return 0;
  });
}

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
      TableReader c(L, -1, "fill.region.ball");
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
      throw std::runtime_error(fmt::format("fill.region: give one of {}",
                                           d == 2 ? "circle, box" : "sphere, box, cylinder"));
    }
    r.finish();
    lua_pop(L, 1);
    t.finish();
    std::vector<std::int64_t> ids = s.sim->fill(f);
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

int l_central_field(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "central_field");
    auto point = t.vector("point", dim(L));
    double strength = t.number("strength");
    t.finish();
    s.sim->set_central_field(point, strength);
    return 0;
  });
}

int l_set_central_strength(lua_State* L) {
  return protect(L, [](lua_State* L) {
    self(L).sim->set_central_strength(read_number(L, 2, "central field strength"));
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
    LuaSim& s = self(L);
    int w = s.sim->wall_id(read_string(L, 2, "set_wall: wall name"));
    TableReader t(L, 3, "set_wall");
    if (t.has("velocity")) s.sim->set_wall_velocity(w, t.vector("velocity", dim(L)));
    if (t.has("angular_velocity"))
      s.sim->set_wall_angular_velocity(w, t.number("angular_velocity"));
    t.finish();
    return 0;
  });
}

int l_wall(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    int w = s.sim->wall_id(read_string(L, 2, "wall name"));
    WallSpec spec = s.sim->wall(w);
    lua_newtable(L);
    lua_pushstring(L, spec.name.c_str());
    lua_setfield(L, -2, "name");
    lua_pushstring(L, spec.type == WallType::plane ? "plane" : "cylinder");
    lua_setfield(L, -2, "type");
    push_vector(L, s.sim->wall_force(w), d);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, s.sim->wall_axial_torque(w));
    lua_setfield(L, -2, "torque");
    if (spec.type == WallType::plane) {
      push_vector(L, spec.point, d);
      lua_setfield(L, -2, "point");
      push_vector(L, spec.velocity, d);
      lua_setfield(L, -2, "velocity");
    } else {
      push_vector(L, spec.center, d);
      lua_setfield(L, -2, "center");
      lua_pushnumber(L, spec.radius);
      lua_setfield(L, -2, "radius");
      lua_pushnumber(L, spec.angular_velocity);
      lua_setfield(L, -2, "angular_velocity");
    }
    return 1;
  });
}

// ---- particles ----
int l_particle(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = dim(L);
    std::int64_t id = particle_id(L, 2, *s.sim);
    lua_newtable(L);
    lua_pushinteger(L, id);
    lua_setfield(L, -2, "id");
    push_vector(L, s.sim->position(id), d);
    lua_setfield(L, -2, "position");
    push_vector(L, s.sim->velocity(id), d);
    lua_setfield(L, -2, "velocity");
    if (d == 2)
      lua_pushnumber(L, s.sim->spin(id)[2]);
    else
      push_vector(L, s.sim->spin(id), 3);
    lua_setfield(L, -2, "spin");
    push_vector(L, s.sim->force(id), d);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, s.sim->radius(id));
    lua_setfield(L, -2, "radius");
    lua_pushnumber(L, s.sim->mass(id));
    lua_setfield(L, -2, "mass");
    lua_pushstring(L, s.sim->materials()[s.sim->material_of(id)].name.c_str());
    lua_setfield(L, -2, "material");
    lua_pushboolean(L, s.sim->is_fixed(id));
    lua_setfield(L, -2, "fixed");
    return 1;
  });
}

int l_particles(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto ids = self(L).sim->particle_ids();
    lua_createtable(L, static_cast<int>(ids.size()), 0);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      lua_pushinteger(L, ids[k]);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
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

// ---- running ----
}  // namespace

// A callback's error that is not a string (error({...}), error(nil)) still names where
// it was raised: the handler runs where the error was raised, before the stack unwinds.
int callback_error_handler(lua_State* L) {
  if (lua_type(L, 1) == LUA_TSTRING || lua_type(L, 1) == LUA_TNUMBER) return 1;
  const char* what = lua_tostring(L, lua_upvalueindex(1));
  push_script_where(L);
  const char* value = luaL_tolstring(L, 1, nullptr);
  lua_pushfstring(L, "%s raised a %s as its error (%s); raise a string: error(\"...\")", what,
                  luaL_typename(L, 1), value);
  lua_remove(L, -2);
  lua_concat(L, 2);
  return 1;
}

void call_lua(lua_State* L, int function_ref, int self_ref, int results, const char* what) {
  lua_pushstring(L, what);
  lua_pushcclosure(L, callback_error_handler, 1);
  const int handler = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, function_ref);
  lua_rawgeti(L, LUA_REGISTRYINDEX, self_ref);
  if (lua_pcall(L, 1, results, handler) != LUA_OK) {
    std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(error)";
    lua_settop(L, handler - 1);
    throw ScriptError(message);
  }
  lua_remove(L, handler);
}

namespace {

// Undoes what a run set up, however it ends (normally, by an error, by Ctrl-C).
struct RunGuard {
  lua_State* L;
  LuaSim& s;
  int stop_ref;
  ~RunGuard() {
    s.running = false;
    if (stop_ref != LUA_NOREF) luaL_unref(L, LUA_REGISTRYINDEX, stop_ref);
  }
};

int l_run(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running)
      throw std::runtime_error("run: cannot run a simulation from inside its own callback");
    TableReader t(L, 2, "run");
    bool has_duration = t.has("duration"), has_steps = t.has("steps");
    if (has_duration == has_steps)
      throw std::runtime_error("run: give exactly one of 'duration' [s] or 'steps'");
    double duration = has_duration ? t.number("duration") : 0;
    std::int64_t steps = has_steps ? t.integer("steps") : 0;
    if (has_duration && !(duration >= 0))
      throw std::runtime_error("run: duration must be >= 0 [s]");
    if (has_steps && steps < 0) throw std::runtime_error("run: steps must be >= 0");
    std::int64_t check_every = t.integer("check_every", 100);
    if (check_every < 1) throw std::runtime_error("run: check_every must be >= 1");
    // stop_when is taken into the registry only after every check has passed.
    t.mark("stop_when");
    t.finish();

    // A restarted scene living through its past: a run that had ended returns what it
    // returned then (after firing its callbacks again); one that was going on when the
    // checkpoint was written fires its callbacks up to there and goes on below.
    SceneContext* ctx = context(L);
    Journal* journal = ctx ? ctx->journal.get() : nullptr;
    if (journal && journal->replaying()) {
      const int results = replay_run(L, s, t);
      if (results >= 0) return results;
    }
    std::int64_t done = 0;
    bool resuming = false;
    if (ctx && ctx->restart && ctx->restart->resume_run && ctx->restart->target == &s) {
      Restart& r = *ctx->restart;
      r.resume_run = false;
      resuming = true;
      s.run_start_step = r.run_start_step;
      s.run_total_steps = r.run_total_steps;
      done = s.sim->step_count() - r.run_start_step;
    }

    const bool first_run = s.sim->step_count() == 0 && !s.header_printed;
    s.sim->ensure_prepared();
    // The run's header: what this scene simulates (and so what it pays for).
    if (first_run && !(ctx && ctx->quiet)) {
      for (const auto& line : s.sim->describe()) std::cerr << "granule: " << line << "\n";
      s.header_printed = true;
    }
    const double dt = s.sim->time_step();
    if (resuming) {
      steps = s.run_total_steps;
    } else {
      if (has_duration) {
        // A step count beyond 2^62 would overflow the counters (and never finish).
        const double n = std::ceil(duration / dt - 1e-9);
        if (!(n < 4.6e18))
          throw std::runtime_error(
              fmt::format("run: duration = {} s is {:.3g} steps of dt = {} s, too many to count",
                          duration, n, dt));
        steps = static_cast<std::int64_t>(std::max(0.0, n));
      }
      s.run_start_step = s.sim->step_count();
      s.run_total_steps = steps;
    }
    int stop_ref = LUA_NOREF;
    if (t.push_function("stop_when")) stop_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    s.running = true;
    RunGuard guard{L, s, stop_ref};

    std::optional<RunProgress> progress;
    if (ctx && ctx->progress) {
      // Runs shorter than this many seconds show no line; tests set it to 0.
      double delay = 2.0;
      if (const char* env = std::getenv("GRANULE_PROGRESS_AFTER")) {
        char* end = nullptr;
        double v = std::strtod(env, &end);
        if (end != env && *end == '\0' && v >= 0 && std::isfinite(v)) delay = v;
      }
      progress.emplace(std::cerr, steps - done,
                       s.sim->time() + static_cast<double>(steps - done) * dt,
                       stop_ref != LUA_NOREF, RunProgress::Clock{}, delay);
    }
    // The engine's runner takes the steps; the scene's criterion, its checkpoints and the
    // user's interrupt are served between its chunks.
    RunHooks hooks;
    hooks.stop_when = [&] {
      if (journal) journal->record_callback(-1);
      call_lua(L, stop_ref, s.self_ref, 1, "the run's stop_when");
      const bool stop = lua_toboolean(L, -1);
      lua_pop(L, 1);
      return stop;
    };
    hooks.write_checkpoint = [&](const std::string& path) { write_checkpoint_now(s, path, true); };
    hooks.interrupt_pending = [] { return interrupt_pending(); };
    if (progress) hooks.progress = [&](std::int64_t n, double time) { progress->update(n, time); };
    std::string interrupt_path = s.checkpoint.path;
    if (interrupt_path.empty())
      interrupt_path =
          (ctx && !ctx->scene_path.empty() ? std::filesystem::path(ctx->scene_path).stem().string()
                                           : std::string("granule")) +
          ".checkpoint.h5";
    RunPlan plan;
    plan.steps = steps;
    plan.done = done;
    plan.check_every = stop_ref != LUA_NOREF ? check_every : 0;
    RunOutcome outcome;
    {
      struct Active {
        Active() { set_run_active(true); }
        ~Active() { set_run_active(false); }
      } active;
      outcome = run_in_chunks(*s.sim, plan, s.checkpoint, interrupt_path, hooks);
    }
    done = outcome.done;
    const bool stopped = outcome.stopped;
    if (outcome.interrupted) {
      // Between two steps, with the checkpoint written: say where and how to go on.
      lua_sethook(L, nullptr, 0, 0);  // the hook the signal also set, to stop script loops
      clear_interrupt();
      if (ctx) ctx->interrupted = true;
      throw std::runtime_error(fmt::format(
          "run interrupted ({}) after {} of {} steps, at t = {} s (step {}); checkpoint "
          "written to {}; continue with: granule run {} --restart {}",
          interrupt_cause(), done, steps, s.sim->time(), s.sim->step_count(), interrupt_path,
          ctx ? ctx->scene_path : std::string("SCENE.lua"), interrupt_path));
    }
    if (progress) progress->finish();
    lua_newtable(L);
    lua_pushinteger(L, done);
    lua_setfield(L, -2, "steps");
    lua_pushnumber(L, s.sim->time());
    lua_setfield(L, -2, "time");
    lua_pushboolean(L, stopped);
    lua_setfield(L, -2, "stopped");
    return 1;
  });
}

// every { steps = N | time = T, function(sim) ... end } -> hook id
int l_every(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "every");
    Hook h;
    h.name = t.string("name", "lua callback");
    h.every_steps = t.integer("steps", 0);
    h.every_time = t.number("time", 0);
    if (h.every_steps < 0 || h.every_time < 0)
      throw std::runtime_error("every: steps and time must be > 0");
    if ((h.every_steps > 0) == (h.every_time > 0))
      throw std::runtime_error("every: give exactly one of steps = N (> 0) or time = T [s] (> 0)");
    t.finish();
    if (lua_geti(L, 2, 1) != LUA_TFUNCTION) {
      lua_pop(L, 1);
      throw std::runtime_error("every: the first entry must be a function(sim)");
    }
    if (lua_rawlen(L, 2) > 1) {
      lua_pop(L, 1);
      throw std::runtime_error("every: give one function, as { steps = N, function(sim) ... end }");
    }
    int ref = luaL_ref(L, LUA_REGISTRYINDEX);
    int self_ref = s.self_ref;
    // The journal notes where each callback fired, so that a restart fires it there again.
    std::shared_ptr<Journal> journal = context(L) ? context(L)->journal : nullptr;
    auto id = std::make_shared<int>(0);
    h.fire = [L, ref, self_ref, journal, id] {
      if (journal && !journal->replaying()) journal->record_callback(*id);
      call_lua(L, ref, self_ref, 0, "the sim:every callback");
    };
    *id = s.sim->add_hook(h);
    s.lua_hooks[*id] = ref;
    lua_pushinteger(L, *id);
    return 1;
  });
}

int l_remove_hook(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::int64_t id = read_integer(L, 2, "remove_hook: hook id");
    // Hook ids are small positive ints; a larger number must not wrap onto a real one.
    if (id < 1 || id > std::numeric_limits<int>::max() || !s.sim->has_hook(static_cast<int>(id)))
      throw std::runtime_error(fmt::format("remove_hook: no hook with id {}", id));
    s.sim->remove_hook(static_cast<int>(id));
    s.lua_hooks.erase(static_cast<int>(id));
    return 0;
  });
}

// sim:set { skin =, time_step =, steps_per_contact =, threads =, pruning = }: change numerical
// settings between runs (the next run re-checks the scene and rebuilds its lists).
int l_set(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running) throw std::runtime_error("set: not from inside a run's callback");
    TableReader t(L, 2, "set");
    if (t.has("skin")) s.sim->set_skin(t.number("skin"));
    if (t.has("time_step")) s.sim->set_time_step(t.number("time_step"));
    if (t.has("steps_per_contact")) s.sim->set_steps_per_contact(t.number("steps_per_contact"));
    if (t.has("threads")) s.sim->set_threads(static_cast<int>(t.integer("threads")));
    if (t.has("pruning")) s.sim->set_pruning(t.boolean("pruning", true));
    t.finish();
    return 0;
  });
}

int l_prepare(lua_State* L) {
  return protect(L, [](lua_State* L) {
    self(L).sim->prepare();
    return 0;
  });
}

// ---- output ----
int l_output(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    SceneContext* ctx = context(L);
    TableReader t(L, 2, "output");
    io::RunOutputSettings o;
    std::string fallback = ctx->output_path;
    if (fallback.empty())
      fallback = ctx->scene_path.empty()
                     ? "granule.h5"
                     : std::filesystem::path(ctx->scene_path).stem().string() + ".h5";
    // -o on the command line wins over the scene's own choice.
    o.path = ctx->output_path.empty() ? t.string("file", fallback) : ctx->output_path;
    // A restarted run writes beside the original's output, never over it (unless -o says so).
    if (!ctx->restart_path.empty() && ctx->output_path.empty()) {
      std::filesystem::path p(o.path);
      o.path =
          (p.parent_path() / (p.stem().string() + "_restarted" + p.extension().string())).string();
    }
    // -o wins, but the scene's own 'file' must still be a file name.
    if (!ctx->output_path.empty() && t.has("file")) (void)t.string("file");
    o.snapshot_every = t.number("snapshot_every", 0);
    o.series_every = t.number("series_every", 0);
    o.xdmf = t.boolean("xdmf", true);
    t.finish();
    o.scene_path = ctx->scene_path;
    o.scene_source = ctx->scene_source;
    o.parameters = ctx->parameter_values;
    o.numeric_parameters = ctx->numeric_parameters;
    // Replaying a restarted scene's past: the output is made (its hooks in their places)
    // but writes nothing; the checkpoint's output is continued when the journal ends.
    o.muted = ctx->journal && ctx->journal->replaying();
    s.output.reset();
    s.output = std::make_unique<io::RunOutput>(*s.sim, o);
    ++s.output_calls;
    if (!o.muted) ctx->outputs_written.push_back(o.path);
    lua_pushstring(L, o.path.c_str());
    return 1;
  });
}

io::RunOutput& output_of(LuaSim& s) {
  if (!s.output) throw std::runtime_error("no output file: call sim:output { ... } first");
  return *s.output;
}

int l_snapshot(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    output_of(s).write_snapshot();
    return 0;
  });
}

std::vector<std::string> read_string_list(lua_State* L, int index, const std::string& what) {
  if (!lua_istable(L, index)) throw std::runtime_error(what + " must be a list of names");
  std::vector<std::string> out;
  lua_Integer n = luaL_len(L, index);
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_geti(L, index, k);
    if (lua_type(L, -1) != LUA_TSTRING) {
      lua_pop(L, 1);
      throw std::runtime_error(fmt::format("{}[{}] must be a string", what, k));
    }
    out.emplace_back(lua_tostring(L, -1));
    lua_pop(L, 1);
  }
  return out;
}

int l_series(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    std::string name = read_string(L, 2, "series name");
    out.declare_series(name, read_string_list(L, 3, "series columns"));
    return 0;
  });
}

int l_append(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    std::string name = read_string(L, 2, "series name");
    if (!lua_istable(L, 3)) throw std::runtime_error("append: expected a list of numbers");
    std::vector<double> row;
    lua_Integer n = luaL_len(L, 3);
    for (lua_Integer k = 1; k <= n; ++k) {
      lua_geti(L, 3, k);
      row.push_back(read_number(L, -1, fmt::format("append '{}' value {}", name, k)));
      lua_pop(L, 1);
    }
    out.append_series(name, row);
    return 0;
  });
}

int l_result(lua_State* L) {
  return protect(L, [](lua_State* L) {
    auto& out = output_of(self(L));
    TableReader t(L, 2, "result");
    for (const auto& key : t.keys()) out.write_result(key, t.number(key.c_str()));
    return 0;
  });
}

int l_close(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.output) s.output->finish();
    s.output.reset();
    return 0;
  });
}

// ---- queries ----
int l_stats(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    GlobalStats g = s.sim->stats();
    lua_newtable(L);
    auto set = [&](const char* k, double v) {
      lua_pushnumber(L, v);
      lua_setfield(L, -2, k);
    };
    set("time", g.time);
    lua_pushinteger(L, g.step);
    lua_setfield(L, -2, "step");
    lua_pushinteger(L, g.particles);
    lua_setfield(L, -2, "particles");
    set("kinetic_energy", g.kinetic_translational + g.kinetic_rotational);
    set("kinetic_energy_translational", g.kinetic_translational);
    set("kinetic_energy_rotational", g.kinetic_rotational);
    push_vector(L, g.momentum, s.sim->dimension());
    lua_setfield(L, -2, "momentum");
    set("angular_momentum_z", g.angular_momentum_z);
    lua_pushinteger(L, g.contacts_particle);
    lua_setfield(L, -2, "contacts_particle");
    lua_pushinteger(L, g.contacts_batched);
    lua_setfield(L, -2, "contacts_batched");
    lua_pushinteger(L, g.contacts_wall);
    lua_setfield(L, -2, "contacts_wall");
    set("max_overlap_ratio", g.max_overlap_ratio);
    set("candidate_pairs", static_cast<double>(g.candidate_pairs));
    set("list_rebuilds", static_cast<double>(g.list_rebuilds));
    set("thread_rebalances", static_cast<double>(g.thread_rebalances));
    set("pair_list_prunes", static_cast<double>(g.pair_list_prunes));
    set("pair_candidates_visited", static_cast<double>(g.pair_candidates_visited));
    return 1;
  });
}

int l_contacts(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int d = s.sim->dimension();
    auto list = s.sim->contacts();
    lua_createtable(L, static_cast<int>(list.size()), 0);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const ContactRecord& c = list[k];
      lua_newtable(L);
      lua_pushinteger(L, c.id_a);
      lua_setfield(L, -2, "a");
      if (c.wall >= 0) {
        lua_pushstring(L, s.sim->wall(c.wall).name.c_str());
        lua_setfield(L, -2, "wall");
      } else {
        lua_pushinteger(L, c.id_b);
        lua_setfield(L, -2, "b");
      }
      lua_pushstring(L, c.model.c_str());
      lua_setfield(L, -2, "model");
      lua_pushnumber(L, c.overlap);
      lua_setfield(L, -2, "overlap");
      lua_pushnumber(L, c.normal_force);
      lua_setfield(L, -2, "normal_force");
      push_vector(L, c.tangential_force, d);
      lua_setfield(L, -2, "tangential_force");
      push_vector(L, c.normal, d);
      lua_setfield(L, -2, "normal");
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

int l_time(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushnumber(L, self(L).sim->time());
    return 1;
  });
}
int l_step_count(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushinteger(L, self(L).sim->step_count());
    return 1;
  });
}
int l_time_step(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    s.sim->ensure_prepared();
    lua_pushnumber(L, s.sim->time_step());
    return 1;
  });
}
int l_time_step_rule(lua_State* L) {
  return protect(L, [](lua_State* L) {
    TimeStepReport r = self(L).sim->time_step_rule();
    lua_newtable(L);
    lua_pushnumber(L, r.rule);
    lua_setfield(L, -2, "rule");
    lua_pushnumber(L, r.stability_limit);
    lua_setfield(L, -2, "stability_limit");
    lua_pushstring(L, r.governing_pair.c_str());
    lua_setfield(L, -2, "governing_pair");
    return 1;
  });
}
int l_describe(lua_State* L) {
  return protect(L, [](lua_State* L) {
    std::string all;
    for (const auto& line : self(L).sim->describe()) all += line + "\n";
    lua_pushstring(L, all.c_str());
    return 1;
  });
}
// Wall-clock seconds spent per stage of the step since the simulation was made.
int l_timings(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const auto& t = self(L).sim->stage_times();
    lua_newtable(L);
    lua_pushnumber(L, t.neighbor);
    lua_setfield(L, -2, "neighbor");
    lua_pushnumber(L, t.force);
    lua_setfield(L, -2, "force");
    lua_pushnumber(L, t.diagnostics);
    lua_setfield(L, -2, "diagnostics");
    lua_pushnumber(L, t.integrate);
    lua_setfield(L, -2, "integrate");
    lua_pushnumber(L, t.hooks);
    lua_setfield(L, -2, "hooks");
    lua_pushnumber(L, t.scatter);
    lua_setfield(L, -2, "scatter");
    lua_pushnumber(L, t.walls);
    lua_setfield(L, -2, "walls");
    lua_pushnumber(L, t.pair_wait);
    lua_setfield(L, -2, "pair_wait");
    return 1;
  });
}
int l_dimension(lua_State* L) {
  return protect(L, [](lua_State* L) {
    lua_pushinteger(L, dim(L));
    return 1;
  });
}

int l_contact_parameters(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::string a = read_string(L, 2, "contact_parameters: first material");
    std::string b = read_string(L, 3, "contact_parameters: second material");
    int ia = s.sim->material_id(a), ib = s.sim->material_id(b);
    const PairTable& table = s.sim->pair_table();
    const PairTable::Entry& e = table.at(ia, ib);
    if (e.model < 0)
      throw std::runtime_error(fmt::format("no contact law between '{}' and '{}'", a, b));
    lua_newtable(L);
    lua_pushstring(L, contact_model_catalogue()[e.model].name.c_str());
    lua_setfield(L, -2, "model");
    for (const auto& [name, value] : table.values(ia, ib)) {
      lua_pushnumber(L, value);
      lua_setfield(L, -2, name.c_str());
    }
    return 1;
  });
}

int l_materials(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const auto& mats = self(L).sim->materials();
    lua_createtable(L, static_cast<int>(mats.size()), 0);
    for (std::size_t k = 0; k < mats.size(); ++k) {
      lua_newtable(L);
      lua_pushstring(L, mats[k].name.c_str());
      lua_setfield(L, -2, "name");
      const std::pair<const char*, double> fields[] = {{"density", mats[k].density},
                                                       {"young", mats[k].young},
                                                       {"poisson", mats[k].poisson},
                                                       {"surface_energy", mats[k].surface_energy}};
      for (const auto& [key, value] : fields) {
        lua_pushnumber(L, value);
        lua_setfield(L, -2, key);
      }
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    return 1;
  });
}

int l_walls(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    lua_createtable(L, s.sim->wall_count(), 0);
    for (int w = 0; w < s.sim->wall_count(); ++w) {
      lua_pushstring(L, s.sim->wall(w).name.c_str());
      lua_rawseti(L, -2, w + 1);
    }
    return 1;
  });
}

int l_simulations(lua_State* L) {
  return protect(L, [](lua_State* L) {
    if (lua_getfield(L, LUA_REGISTRYINDEX, simulations_key) != LUA_TTABLE) {
      lua_pop(L, 1);
      lua_newtable(L);
    }
    // A copy, so that the caller cannot edit the session's list.
    lua_newtable(L);
    lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -2));
    for (lua_Integer k = 1; k <= n; ++k) {
      lua_rawgeti(L, -2, k);
      lua_rawseti(L, -2, k);
    }
    return 1;
  });
}

int l_gc(lua_State* L) {
  auto* s = static_cast<LuaSim*>(luaL_testudata(L, 1, metatable_name));
  if (s) s->~LuaSim();  // output first (member order reversed), then the simulation
  return 0;
}

int l_tostring(lua_State* L) {
  auto* s = static_cast<LuaSim*>(luaL_testudata(L, 1, metatable_name));
  if (!s || !s->sim) {
    lua_pushstring(L, "simulation (closed)");
  } else {
    lua_pushfstring(L, "simulation (%dD, %d particles, t = %f s)", s->sim->dimension(),
                    static_cast<int>(s->sim->particle_count()), s->sim->time());
  }
  return 1;
}

// simulation { dimension = 2|3, time_step = s, steps_per_contact = n, skin = m,
//              record_contacts = bool, overlap_warning = f, periodic = { axis = "z", origin = m,
//              length = m } }
int l_simulation(lua_State* L) {
  return protect(L, [](lua_State* L) {
    // `granule sweep` checking parameters: a scene that reaches its simulation has declared
    // none, and must not go on to run it (scene.hpp, SceneContext::parameters_only).
    if (SceneContext* ctx = context(L); ctx && ctx->parameters_only) {
      ctx->stopped_after_parameters = true;
      throw std::runtime_error(parameters_checked_stop);
    }
    if (lua_isnoneornil(L, 1)) lua_newtable(L), lua_replace(L, 1);
    TableReader t(L, 1, "simulation");
    int d = static_cast<int>(t.integer("dimension", 3));
    auto sim = make_simulation(d);
    // Before the settings, so that their warnings (threads) follow --quiet.
    bool quiet = context(L) && context(L)->quiet;
    sim->set_warning_handler([quiet](const std::string& m) {
      if (!quiet) std::cerr << "warning: " << m << "\n";
    });
    sim->set_time_step(t.number("time_step", 0));
    sim->set_steps_per_contact(t.number("steps_per_contact", 40));
    sim->set_skin(t.number("skin", 0));
    sim->set_record_contacts(t.boolean("record_contacts", false));
    if (t.has("overlap_warning")) sim->set_overlap_warning(t.number("overlap_warning"));
    sim->set_threads(static_cast<int>(t.integer("threads", 0)));
    if (context(L) && context(L)->threads > 0) sim->set_threads(context(L)->threads);
    if (t.push_table("periodic")) {
      TableReader p(L, -1, "simulation.periodic");
      std::string axis = p.string("axis", "z");
      int a = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
      if (a < 0) throw std::runtime_error("simulation.periodic: axis must be 'x', 'y' or 'z'");
      double origin = p.number("origin", 0), length = p.number("length");
      p.finish();
      lua_pop(L, 1);
      sim->set_periodic(a, origin, length);
    }
    t.finish();
    void* mem = lua_newuserdatauv(L, sizeof(LuaSim), 0);
    auto* s = new (mem) LuaSim();
    s->sim = std::move(sim);
    s->context = context(L);
    // The scene's first simulation continues the checkpoint.
    if (SceneContext* ctx = context(L); ctx && ctx->restart && !ctx->restart->target)
      ctx->restart->target = s;
    // And writes its checkpoints where the command line says.
    if (SceneContext* ctx = context(L);
        ctx && (!ctx->checkpoint_path.empty() || ctx->checkpoint_every_seconds > 0) &&
        !ctx->checkpoint_assigned) {
      ctx->checkpoint_assigned = true;
      s->checkpoint.path =
          !ctx->checkpoint_path.empty()
              ? ctx->checkpoint_path
              : std::filesystem::path(ctx->scene_path).stem().string() + ".checkpoint.h5";
      s->checkpoint.every_seconds = ctx->checkpoint_every_seconds;
      s->checkpoint_path_fixed = true;
    }
    luaL_setmetatable(L, metatable_name);
    lua_pushvalue(L, -1);
    s->self_ref = luaL_ref(L, LUA_REGISTRYINDEX);
    if (lua_getfield(L, LUA_REGISTRYINDEX, simulations_key) != LUA_TTABLE) {
      lua_pop(L, 1);
      lua_newtable(L);
      lua_pushvalue(L, -1);
      lua_setfield(L, LUA_REGISTRYINDEX, simulations_key);
    }
    lua_pushvalue(L, -2);
    lua_rawseti(L, -2, static_cast<lua_Integer>(lua_rawlen(L, -2)) + 1);
    lua_pop(L, 1);
    return 1;
  });
}

const luaL_Reg methods[] = {
    {"material", l_material},
    {"contact", l_contact},
    {"set_contact", l_set_contact},
    {"wall_plane", l_wall_plane},
    {"wall_cylinder", l_wall_cylinder},
    {"set_wall", l_set_wall},
    {"wall", l_wall},
    {"add_particle", l_add_particle},
    {"fill", l_fill},
    {"gravity", l_gravity},
    {"central_field", l_central_field},
    {"set_central_strength", l_set_central_strength},
    {"central_strength", l_central_strength},
    {"remove_central_field", l_remove_central_field},
    {"particle", l_particle},
    {"particles", l_particles},
    {"set_velocity", l_set_velocity},
    {"set_position", l_set_position},
    {"set_spin", l_set_spin},
    {"remove_particle", l_remove_particle},
    {"run", l_run},
    {"every", l_every},
    {"remove_hook", l_remove_hook},
    {"prepare", l_prepare},
    {"set", l_set},
    {"output", l_output},
    {"snapshot", l_snapshot},
    {"series", l_series},
    {"append", l_append},
    {"result", l_result},
    {"close", l_close},
    {"stats", l_stats},
    {"contacts", l_contacts},
    {"time", l_time},
    {"step_count", l_step_count},
    {"time_step", l_time_step},
    {"time_step_rule", l_time_step_rule},
    {"describe", l_describe},
    {"dimension", l_dimension},
    {"timings", l_timings},
    // wrap_agglomerate.cpp (dissertation chapter 7)
    {"load_particles", bound<load_particles>},
    {"save_contact_histories", bound<save_contact_histories>},
    {"bonds", bound<bonds>},
    {"fragments", bound<fragments>},
    {"breakage", bound<breakage>},
    {"scale_velocities", bound<scale_velocities>},
    {"contact_parameters", l_contact_parameters},
    {"materials", l_materials},
    {"walls", l_walls},
    {"picture", l_picture},
    {nullptr, nullptr},
};
}  // namespace

// __index of the method table: a misspelt method is an error that suggests the nearest name.
int unknown_method(lua_State* L) {
  {
    const char* name = lua_tostring(L, 2);
    std::vector<std::string> known;
    for (const luaL_Reg* m = methods; m->name; ++m) known.emplace_back(m->name);
    std::string hint = name ? nearest_name(name, known) : "";
    std::string message =
        fmt::format("simulation has no method '{}'{}", name ? name : "?",
                    hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint));
    push_script_where(L);
    lua_pushstring(L, message.c_str());
    lua_concat(L, 2);
  }  // the strings are destroyed before lua_error longjmps
  return lua_error(L);
}

SimulationBase& simulation_argument(lua_State* L) {
  return *self(L).sim;
}

void open_simulation(lua_State* L) {
  luaL_newmetatable(L, metatable_name);
  lua_newtable(L);
  // Every method goes through the arity check of its documentation entry; a
  // method without an entry is still callable, and the docs test names it.
  for (const luaL_Reg* table : {methods, diagnostic_methods, checkpoint_methods, schedule_methods})
    for (const luaL_Reg* m = table; m->name; ++m) {
      const FunctionDoc* doc = find_doc(std::string("sim:") + m->name);
      if (doc && std::string(doc->name) == std::string("sim:") + m->name)
        push_checked(L, *doc, m->func);
      else
        lua_pushcfunction(L, m->func);
      push_journaled(L, (std::string("sim:") + m->name).c_str(), journal_kind(m->name));
      lua_setfield(L, -2, m->name);
    }
  // Unknown method names are errors with a suggestion, not silent nils.
  lua_newtable(L);
  lua_pushcfunction(L, unknown_method);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, l_gc);
  lua_setfield(L, -2, "__gc");
  lua_pushcfunction(L, l_tostring);
  lua_setfield(L, -2, "__tostring");
  lua_pop(L, 1);
  push_checked(L, *find_doc("simulation"), l_simulation);
  push_journaled(L, "simulation", Journal::Kind::build);
  lua_setglobal(L, "simulation");
  push_checked(L, *find_doc("simulations"), l_simulations);
  lua_setglobal(L, "simulations");
  if (SceneContext* ctx = context(L)) {
    ctx->journal = std::make_shared<Journal>();
    if (!ctx->restart_path.empty()) ctx->begin_replay = [ctx] { begin_restart(*ctx); };
  }
}

}  // namespace granule::lua
