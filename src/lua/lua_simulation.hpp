// The Simulation userdata shared by the binding files (lua_simulation.cpp and
// the wrap_*.cpp files that add methods to it).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <limits>
#include <lua.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/state.hpp"
#include "engine/run_loop.hpp"
#include "engine/simulation_base.hpp"
#include "io/run_output.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"

namespace granule::lua {

inline constexpr const char* simulation_metatable = "granule.Simulation";

// Checkpoints and restarts (wrap_checkpoint.cpp). A restarted scene runs its
// script from the top with the checkpoint's journal in replay (journal.hpp):
// the script lives through its past exactly as the first run did, without
// computing it, and when the journal is used up the checkpoint's state is
// loaded and the scene goes on for real.
struct LuaSim;

struct Restart {
  std::string path;
  std::unique_ptr<StateBlob> state;
  std::vector<std::uint8_t> journal;
  int journal_format = 1;  // Journal::format of the run that wrote it (1: no argument digests)
  std::int64_t run_start_step = 0;   // the run in progress: where it began
  std::int64_t run_total_steps = 0;  // and how many steps it was to take
  double run_end_time = std::numeric_limits<double>::quiet_NaN();  // its end [s], if a duration's
  bool has_end_time = false;      // the checkpoint says (a build before end times did not)
  double run_planned_dt = 0;      // the time step its steps were counted with (0: not saved)
  bool in_run = false;            // the checkpoint was taken inside a run
  std::int64_t output_index = 0;  // which sim:output call made the open output (0: none)
  LuaSim* target = nullptr;       // the scene's first simulation, which continues it
  bool applied = false;
  bool resume_run = false;  // the next sim:run to reach the real path continues the run
};

struct LuaSim {
  std::unique_ptr<SimulationBase> sim;
  std::unique_ptr<io::RunOutput> output;
  SceneContext* context = nullptr;  // the scene that made it (its journal, its -D values)
  int self_ref = LUA_NOREF;
  bool running = false;
  bool header_printed = false;
  // run bookkeeping, for checkpoints
  std::int64_t run_start_step = 0, run_total_steps = 0;
  double run_end_time = std::numeric_limits<double>::quiet_NaN();  // a duration run's end [s]
  double run_planned_dt = 0;              // the time step its steps were counted with [s]
  std::int64_t output_calls = 0;          // sim:output calls so far (which output is open)
  std::vector<std::string> output_paths;  // the files its sim:output calls opened
  struct LuaHook {
    int ref = LUA_NOREF;  // registry ref of its function
    std::string what;     // "sim:every callback 'name'", for its errors
  };
  std::map<int, LuaHook> lua_hooks;  // sim:every hook id -> its function
  CheckpointPlan checkpoint;
  bool checkpoint_path_fixed = false;  // --checkpoint named the file: sim:checkpoint keeps it
  // Made while a restart replayed the scene, and not the simulation it continues:
  // its calls were answered from the journal, so its engine holds no state, and
  // any call after the restart took over is refused rather than run on nothing.
  bool rebuilt_without_state = false;
};

// Calls the Lua function at registry `function_ref` with the simulation at `self_ref`,
// leaving `results` values, under lua_pcall with a message handler: an error becomes
// ScriptError "what: file:line: message" followed by the traceback from where it was
// raised (the callback's own frames, gone once lua_pcall returns).
void call_lua(lua_State* L, int function_ref, int self_ref, int results, const std::string& what);
// A restarted scene's sim:run while the journal replays (wrap_checkpoint.cpp): fires
// the callbacks the run fired before the checkpoint and returns the number of results
// it pushed (the run had ended), or -1 when the journal ended inside the run, which
// then goes on for real. `run` is the run's argument table.
int replay_run(lua_State* L, LuaSim& s, TableReader& run);

// Writes a checkpoint of `s` now (between steps), with the run bookkeeping.
void write_checkpoint_now(LuaSim& s, const std::string& path, bool in_run);
// InputError when `path` is the simulation's output or its scene file: a
// checkpoint written there would replace it.
void refuse_checkpoint_over(const LuaSim& s, const std::string& path);
// A checkpoint file the scene or the command line names must lie in a folder that
// exists and may be written (checked when it is named, not at the first signal).
void refuse_unwritable_checkpoint(const std::string& path);
// --restart: reads the checkpoint, checks the -D values and the scene against it and
// starts the journal's replay (before the scene's first journaled call).
void begin_restart(SceneContext& ctx);

// The simulation at stack index 1; throws (use inside protect()) if it is not one.
LuaSim& self(lua_State* L);
// The same for the calls that read only the global totals (sim:stats()): a
// spread scene's callback then keeps its shares (SimulationBase::set_pending_gather).
LuaSim& self_totals(lua_State* L);
// The simulation, neither gathered nor reduced: for what every rank of a spread
// scene holds alike (the time, the step, the dimension, the walls), read or
// set by every rank alike (SimulationBase::set_pending_gather).
LuaSim& self_kept(lua_State* L);

// The simulation a method was called on (argument 1); throws std::runtime_error
// if it is not a simulation or has been closed.
SimulationBase& simulation_argument(lua_State* L);

int l_picture(lua_State* L);  // sim:picture { ... }, wrap_picture.cpp

// Methods added by wrap_diagnostics.cpp.
extern const luaL_Reg diagnostic_methods[];
// Methods added by wrap_checkpoint.cpp.
extern const luaL_Reg checkpoint_methods[];
// Methods added by wrap_schedule.cpp.
extern const luaL_Reg schedule_methods[];

}  // namespace granule::lua
