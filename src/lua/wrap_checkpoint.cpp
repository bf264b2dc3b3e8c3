// sim:checkpoint { file = ..., every_steps = N, every_seconds = S } and
// sim:save_checkpoint(file): checkpoint files that `granule run --restart`
// continues bit-identically (see LuaSim in lua_simulation.hpp).
#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"

namespace granule::lua {

void write_checkpoint_now(LuaSim& s, const std::string& path, bool in_run) {
  StateBlob state = s.sim->save_state();
  std::vector<std::int64_t> steps, stopped;
  for (const auto& r : s.completed_runs) {
    steps.push_back(r.steps);
    stopped.push_back(r.stopped ? 1 : 0);
  }
  state.integers["lua.completed_steps"] = steps;
  state.integers["lua.completed_stopped"] = stopped;
  state.integers["lua.current"] = {in_run ? 1 : 0, s.run_start_step, s.run_total_steps};
  io::write_checkpoint(path, state,
                       {{"program", std::string("granule ") + GRANULE_VERSION},
                        {"step", std::to_string(s.sim->step_count())},
                        {"time", fmt::format("{:.17g}", s.sim->time())}});
  s.checkpoint.last_step = s.sim->step_count();
  s.checkpoint.last_wall = std::chrono::steady_clock::now();
}

std::unique_ptr<Restart> read_restart(const std::string& path) {
  auto r = std::make_unique<Restart>();
  r->path = path;
  r->state = std::make_unique<StateBlob>(io::read_checkpoint(path));
  const auto& steps = r->state->i("lua.completed_steps");
  const auto& stopped = r->state->i("lua.completed_stopped");
  const auto& current = r->state->i("lua.current");
  if (steps.size() != stopped.size() || current.size() != 3)
    throw InputError(fmt::format("checkpoint {}: damaged run bookkeeping", path));
  for (std::size_t k = 0; k < steps.size(); ++k)
    r->completed.push_back({steps[k], stopped[k] != 0});
  r->in_run = current[0] != 0;
  r->run_start_step = current[1];
  r->run_total_steps = current[2];
  return r;
}

namespace {

// sim:checkpoint { file = "run.chk.h5", every_steps = 100000, every_seconds = 600 }
int l_checkpoint(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "checkpoint");
    std::string file = t.string("file");
    std::int64_t every_steps = t.integer("every_steps", 0);
    double every_seconds = t.number("every_seconds", 0);
    t.finish();
    if (file.empty()) throw InputError("checkpoint: 'file' must not be empty");
    if (every_steps < 0) throw InputError("checkpoint: every_steps must be >= 0");
    if (!(every_seconds >= 0) || !std::isfinite(every_seconds))
      throw InputError("checkpoint: every_seconds must be >= 0 [s of wall time]");
    if (every_steps == 0 && every_seconds == 0)
      throw InputError("checkpoint: give every_steps > 0 or every_seconds > 0");
    s.checkpoint.path = file;
    s.checkpoint.every_steps = every_steps;
    s.checkpoint.every_seconds = every_seconds;
    s.checkpoint.last_step = s.sim->step_count();
    s.checkpoint.last_wall = std::chrono::steady_clock::now();
    return 0;
  });
}

// sim:save_checkpoint("file.h5"): now, between runs.
int l_save_checkpoint(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running)
      throw InputError("save_checkpoint: not from inside a run's callback (use sim:checkpoint)");
    std::string file = read_string(L, 2, "save_checkpoint: file");
    s.sim->ensure_prepared();
    write_checkpoint_now(s, file, false);
    return 0;
  });
}

}  // namespace

const luaL_Reg checkpoint_methods[] = {
    {"checkpoint", l_checkpoint},
    {"save_checkpoint", l_save_checkpoint},
    {nullptr, nullptr},
};

}  // namespace granule::lua
