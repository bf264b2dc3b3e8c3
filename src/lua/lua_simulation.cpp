// simulation { ... }, simulations() and the Simulation userdata's metatable: the
// one table of its methods (defined by topic in the wrap_*.cpp files), the
// misspelt-method error, __gc and __tostring. Bindings only: each method reads
// its arguments, calls SimulationBase, pushes results.
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
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

namespace {
LuaSim& open_self(lua_State* L) {
  void* p = luaL_testudata(L, 1, simulation_metatable);
  if (!p) throw std::runtime_error("expected a simulation: call methods as sim:method(...)");
  auto* s = static_cast<LuaSim*>(p);
  if (!s->sim) throw std::runtime_error("this simulation has been closed");
  if (s->rebuilt_without_state && s->context && restart_applied(*s->context))
    throw InputError(
        "restart: this is not the scene's first simulation, whose state the checkpoint holds: "
        "the restart rebuilt it without its particles and state, so it cannot be used after the "
        "point the checkpoint was written (a scene restarts its first simulation only)");
  return *s;
}
}  // namespace

LuaSim& self(lua_State* L) {
  LuaSim& s = open_self(L);
  s.sim->ensure_whole();  // a spread scene's callback: made whole before the call
  return s;
}

LuaSim& self_kept(lua_State* L) {
  return open_self(L);
}

LuaSim& self_totals(lua_State* L) {
  LuaSim& s = open_self(L);
  s.sim->ensure_totals();
  return s;
}

int dim(lua_State* L) {
  return self_kept(L).sim->dimension();
}

std::int64_t particle_id(lua_State* L, int index, const SimulationBase& sim) {
  std::int64_t id = read_integer(L, index, "particle id");
  if (!sim.has_particle(id)) throw InputError(fmt::format("no particle with id {}", id));
  return id;
}

namespace {
const char* metatable_name = simulation_metatable;
// The list of simulations made in this state, for simulations() and the REPL.
const char* simulations_key = "granule.simulations";

// A method defined in a wrap_*.cpp file, given the checked simulation.
template <int (*Method)(lua_State*, SimulationBase&)>
int bound(lua_State* L) {
  return protect(L, [](lua_State* L) { return Method(L, *self(L).sim); });
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
  if (s && s->context && s->context->first_simulation == s) s->context->first_simulation = nullptr;
  if (s && s->context && s->output && !s->context->scene_error.empty())
    s->output->note_scene_error(s->context->scene_error);
  if (s) s->~LuaSim();  // output first (member order reversed), then the simulation
  return 0;
}

int l_tostring(lua_State* L) {
  auto* s = static_cast<LuaSim*>(luaL_testudata(L, 1, metatable_name));
  if (!s || !s->sim) {
    lua_pushstring(L, "simulation (closed)");
  } else {
    s->sim->ensure_whole();
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
    const std::int64_t dimension = t.integer("dimension", 3);
    if (dimension != 2 && dimension != 3)
      throw InputError(fmt::format("simulation: dimension must be 2 or 3, got {}", dimension));
    const int d = static_cast<int>(dimension);
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
    sim->set_threads(t.integer("threads", 0));
    if (context(L) && context(L)->threads > 0) sim->set_threads(context(L)->threads);
    if (t.push_table("periodic")) {
      // A list of axes ({ { axis = 'x', ... }, { axis = 'y', ... } }): one is all there is.
      if (lua_rawlen(L, -1) > 0)
        throw std::runtime_error(
            "simulation.periodic: one periodic axis only, given as periodic = { axis =, origin =, "
            "length = } (a list of axes, or values without their names, is not read)");
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
    else if (ctx && ctx->restart && !ctx->restart->applied)
      s->rebuilt_without_state = true;
    if (SceneContext* ctx = context(L); ctx && !ctx->first_simulation) ctx->first_simulation = s;
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
    {"wall_mesh", l_wall_mesh},
    {"wall_polyline", l_wall_polyline},
    {"wall_disk", l_wall_disk},
    {"wall_cone", l_wall_cone},
    {"set_wall", l_set_wall},
    {"wall", l_wall},
    {"add_particle", l_add_particle},
    {"fill", l_fill},
    {"gravity", l_gravity},
    {"set_damping", l_set_damping},
    {"damping", l_damping},
    {"central_field", l_central_field},
    {"set_central_strength", l_set_central_strength},
    {"central_strength", l_central_strength},
    {"remove_central_field", l_remove_central_field},
    {"particle", l_particle},
    {"particles", l_particles},
    {"set_velocity", l_set_velocity},
    {"set_position", l_set_position},
    {"set_spin", l_set_spin},
    {"set_fixed", l_set_fixed},
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
    {"arrays", l_arrays},
    {"contact_arrays", l_contact_arrays},
    {"table", l_table},
    {"plot", l_plot},
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
    {"bond", l_bond},
    {"bond_counts", l_bond_counts},
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
