// The Simulation userdata shared by the binding files (lua_simulation.cpp and
// the wrap_*.cpp files that add methods to it).
#pragma once

#include <atomic>
#include <chrono>
#include <lua.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/simulation_base.hpp"
#include "core/state.hpp"
#include "io/run_output.hpp"

namespace granule::lua {

inline constexpr const char* simulation_metatable = "granule.Simulation";

// Checkpoints and restarts (wrap_checkpoint.cpp). A restarted scene runs its
// script from the top: the sim:run calls that had finished before the
// checkpoint return at once, and the one that was running loads the
// checkpoint and continues it, so the script's own stage logic is replayed.
struct CheckpointPlan {
  std::string path;              // where periodic checkpoints go
  std::int64_t every_steps = 0;  // 0: not by steps
  double every_seconds = 0;      // wall-clock seconds; 0: not by time
  std::int64_t last_step = -1;   // step of the last checkpoint written
  std::chrono::steady_clock::time_point last_wall = std::chrono::steady_clock::now();
};

struct RunRecord {
  std::int64_t steps = 0;
  bool stopped = false;
};

struct Restart {
  std::string path;
  std::unique_ptr<StateBlob> state;
  std::vector<RunRecord> completed;  // runs that had ended before the checkpoint
  std::int64_t run_start_step = 0;   // the run in progress: where it began
  std::int64_t run_total_steps = 0;  // and how many steps it was to take
  bool in_run = false;               // the checkpoint was taken inside a run
  bool applied = false;
};

struct LuaSim {
  std::unique_ptr<SimulationBase> sim;
  std::unique_ptr<io::RunOutput> output;
  int self_ref = LUA_NOREF;
  bool running = false;
  bool header_printed = false;
  // run bookkeeping, for checkpoints
  std::vector<RunRecord> completed_runs;
  std::int64_t run_start_step = 0, run_total_steps = 0;
  CheckpointPlan checkpoint;
  std::unique_ptr<Restart> restart;  // set when this scene continues a checkpoint
};

// Writes a checkpoint of `s` now (between steps), with the run bookkeeping.
void write_checkpoint_now(LuaSim& s, const std::string& path, bool in_run);
// Reads a checkpoint for --restart (the first simulation of the scene takes it).
std::unique_ptr<Restart> read_restart(const std::string& path);

// The simulation at stack index 1; throws (use inside protect()) if it is not one.
LuaSim& self(lua_State* L);

// The simulation a method was called on (argument 1); throws std::runtime_error
// if it is not a simulation or has been closed.
SimulationBase& simulation_argument(lua_State* L);

int l_picture(lua_State* L);  // sim:picture { ... }, wrap_picture.cpp

// Methods added by wrap_diagnostics.cpp.
extern const luaL_Reg diagnostic_methods[];
// Methods added by wrap_checkpoint.cpp.
extern const luaL_Reg checkpoint_methods[];

}  // namespace granule::lua
