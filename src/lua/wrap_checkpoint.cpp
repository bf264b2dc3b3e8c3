// sim:checkpoint { file = ..., every_steps = N, every_seconds = S } and
// sim:save_checkpoint(file): checkpoint files that `granule run --restart`
// continues bit-identically (see LuaSim in lua_simulation.hpp).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "io/case_record.hpp"
#include "io/checkpoint.hpp"
#include "io/same_file.hpp"
#include "lua/journal.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/lua_util.hpp"
#include "lua/scene.hpp"

namespace granule::lua {

namespace {

// -D values as "name=value" lines, in name order.
std::string overrides_text(const SceneContext& ctx) {
  std::string text;
  for (const auto& [name, value] : ctx.overrides) text += name + "=" + value + "\n";
  return text;
}

std::map<std::string, std::string> parse_overrides(const std::string& text) {
  std::map<std::string, std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    const std::size_t eq = line.find('=');
    if (eq != std::string::npos) out[line.substr(0, eq)] = line.substr(eq + 1);
    start = end + 1;
  }
  return out;
}

// The first line at which two texts differ (1-based).
std::size_t first_differing_line(const std::string& a, const std::string& b) {
  std::size_t line = 1;
  for (std::size_t k = 0; k < a.size() && k < b.size(); ++k) {
    if (a[k] != b[k]) return line;
    if (a[k] == '\n') ++line;
  }
  return line;
}

// The journal's end: the checkpoint's state, diagnostics and output take over.
void take_over(SceneContext& ctx) {
  Restart& r = *ctx.restart;
  if (!r.target)
    throw InputError(fmt::format(
        "restart: the scene had made no simulation when the checkpoint {} was written", r.path));
  LuaSim& s = *r.target;
  s.sim->load_state(*r.state);
  s.sim->load_diagnostics(*r.state);  // after the state: it needs the contact lists
  if (r.output_index > 0 && r.output_index == s.output_calls && s.output) {
    s.output->resume(*r.state, ctx.all_ranks);
    ctx.outputs_written.push_back(s.output->path());
  } else {
    s.output.reset();  // an output the scene had closed before the checkpoint
  }
  r.state.reset();
  r.applied = true;
  r.resume_run = r.in_run;
  if (!ctx.quiet)
    std::cerr << fmt::format("granule: continuing from {} at step {} (t = {:.6g} s)\n", r.path,
                             s.sim->step_count(), s.sim->time());
}

// The journal's end may come inside any call of the scene, a callback's too: a failure
// here is the restart's, not that call's (SceneContext::restart_failure).
void apply_restart(SceneContext& ctx) {
  try {
    take_over(ctx);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    ctx.restart_failure = what.rfind("restart", 0) == 0
                              ? what
                              : fmt::format("restart from {}: {}", ctx.restart->path, what);
    throw InputError(ctx.restart_failure);
  }
}

}  // namespace

bool restart_applied(const SceneContext& ctx) {
  return ctx.restart && ctx.restart->applied;
}

void refuse_checkpoint_over(const LuaSim& s, const std::string& path) {
  if (s.output && io::same_file(path, s.output->path()))
    throw InputError(fmt::format(
        "checkpoint {}: that file is this simulation's output; a checkpoint there would replace "
        "the results it holds: give the checkpoint another name (sim:checkpoint {{ file = }}, "
        "--checkpoint)",
        path));
  if (s.context && io::same_file(path, s.context->scene_path))
    throw InputError(fmt::format(
        "checkpoint {}: that is the scene file; give the checkpoint another name", path));
  if (io::names_non_file(path))
    throw InputError(fmt::format(
        "checkpoint {}: that is not a plain file (a device, a pipe or a folder); a checkpoint "
        "replaces its file: give a file's name",
        path));
}

void refuse_unwritable_checkpoint(const std::string& path) {
  // Known before the run, not when a signal's checkpoint finds no folder to write in.
  // (Under mpirun every rank checks rank 0's folder, the ranks other than 0 writing
  // into scratch folders: the scene then fails alike on every rank.)
  std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(
        fmt::format("checkpoint {}: the folder {} does not exist; create it or name another file",
                    path, folder.string()));
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError(fmt::format(
        "checkpoint {}: the folder {} is not writable; name a file in a folder this run may "
        "write in",
        path, folder.string()));
}

std::string interrupt_checkpoint_path(const LuaSim& s) {
  if (!s.checkpoint.path.empty()) return s.checkpoint.path;
  const SceneContext* ctx = s.context;
  return (ctx && !ctx->scene_path.empty() ? std::filesystem::path(ctx->scene_path).stem().string()
                                          : std::string("granule")) +
         ".checkpoint.h5";
}

std::string continue_hint(const SceneContext* ctx, const std::string& checkpoint) {
  // Spread over ranks, rank 0 names the checkpoint; the others wrote a scratch copy.
  if (ctx && ctx->rank > 0) return "";
  // The command that continues it: the same -D values (a restart refuses others)
  // and the same -o, which the restart then continues rather than writing beside it;
  // its later checkpoints where this run's went (a scene's own sim:checkpoint is
  // in the scene, which the restart runs again).
  std::string again = ctx ? ctx->scene_path : std::string("SCENE.lua");
  if (ctx) {
    for (const auto& [name, value] : ctx->overrides) again += " -D " + name + "=" + value;
    if (!ctx->output_path.empty()) again += " -o " + ctx->output_path;
    if (!ctx->checkpoint_path.empty()) again += " --checkpoint " + ctx->checkpoint_path;
    if (ctx->checkpoint_every_seconds > 0)
      again += fmt::format(" --checkpoint-every {:g}", ctx->checkpoint_every_seconds);
  }
  // A run spread over ranks: the command names the rank count it ran on (any
  // count restarts it, docs/parallel.md).
  const std::string launcher =
      ctx && ctx->ranks > 1 ? fmt::format("mpirun -np {} ", ctx->ranks) : std::string();
  return fmt::format("; checkpoint written to {}; continue with: {}granule run {} --restart {}",
                     checkpoint, launcher, again, checkpoint);
}

std::string checkpoint_between_runs(SceneContext& ctx) {
  LuaSim* s = ctx.first_simulation;
  // A restart stopped while it still replays the scene's past has nothing new to keep.
  if (ctx.journal && ctx.journal->replaying() && !ctx.restart_path.empty() && ctx.rank == 0)
    return fmt::format(
        "; the restart was still replaying the scene's past, so no checkpoint was written: "
        "continue from {} again",
        ctx.restart_path);
  // Ranks would each stop at another point of the script: no common state to keep.
  if (!s || !s->sim || ctx.repl || ctx.ranks > 1 || (ctx.journal && ctx.journal->replaying()))
    return "";
  // Before the first step there is nothing computed to keep: the scene run again
  // gets as far in as long (and a restart would replay a half-made setup, a fill cut
  // short, that no journal holds).
  if (s->sim->step_count() == 0)
    return "; nothing was computed yet, so no checkpoint was written: run the scene again";
  const std::string path = interrupt_checkpoint_path(*s);
  write_checkpoint_now(*s, path, false);  // refuses the output's or the scene's file
  return continue_hint(&ctx, path);
}

void write_checkpoint_now(LuaSim& s, const std::string& path, bool in_run) {
  refuse_checkpoint_over(s, path);
  s.sim->settle_moved_bonds();  // as the next step would: the restart does not replay the moves
  StateBlob state = s.sim->save_state();
  s.sim->save_diagnostics(state);
  // The scene's record: what it saw (the journal), what it was given (-D, its source),
  // which run was going on, and how far the open output had got.
  SceneContext* ctx = s.context;
  if (ctx && ctx->journal) state.bytes["lua.journal"] = ctx->journal->bytes();
  state.integers["lua.journal_format"] = {ctx && ctx->journal ? ctx->journal->format_in_use()
                                                              : Journal::format};
  state.texts["lua.overrides"] = ctx ? overrides_text(*ctx) : std::string();
  state.texts["lua.scene_source"] = ctx ? ctx->scene_source : std::string();
  if (ctx) {  // "digest path" lines, in the order the scene required them
    std::string modules;
    for (const auto& [file, digest] : ctx->module_sources) modules += digest + " " + file + "\n";
    state.texts["lua.modules"] = modules;
  }
  // At the REPL the journal holds what was typed at the prompt too, which no scene file
  // replays (begin_restart refuses such a checkpoint by name).
  if (ctx && ctx->repl_prompt) state.texts["lua.written_at"] = "repl";
  state.integers["lua.current"] = {in_run ? 1 : 0, s.run_start_step, s.run_total_steps};
  // The run's end time, if it is a run of a duration: {1, t, dt its steps were
  // counted with}; else {0, 0, 0}.
  const bool timed = std::isfinite(s.run_end_time) && in_run;
  state.doubles["lua.run_end_time"] = {timed ? 1.0 : 0.0, timed ? s.run_end_time : 0.0,
                                       timed ? s.run_planned_dt : 0.0};
  state.integers["lua.output"] = {s.output ? s.output_calls : 0};
  if (s.output) s.output->save_mark(state);
  io::write_checkpoint(path, state,
                       {{"program", std::string("granule ") + GRANULE_VERSION},
                        {"step", std::to_string(s.sim->step_count())},
                        {"time", fmt::format("{:.17g}", s.sim->time())}});
  s.checkpoint.last_step = s.sim->step_count();
  s.checkpoint.last_wall = std::chrono::steady_clock::now();
}

int replay_run(lua_State* L, LuaSim& s, TableReader& run) {
  Journal& journal = *s.context->journal;
  s.running = true;  // as in the first run: its callbacks may not run or set the simulation
  struct Running {
    LuaSim& s;
    ~Running() { s.running = false; }
  } running{s};
  bool after_callback = false;
  while (journal.replaying()) {
    const Journal::Next next = journal.peek(after_callback);
    if (next == Journal::Next::results) return journal.push_results(L);
    if (next == Journal::Next::error) {
      journal.push_error(L);
      std::string message = lua_tostring(L, -1) ? lua_tostring(L, -1) : "(error object)";
      lua_pop(L, 1);
      throw ScriptError(message);
    }
    if (next == Journal::Next::end) break;
    const std::int64_t id = journal.take_callback();
    if (id < 0) {
      if (!run.push_function("stop_when"))
        throw std::runtime_error(
            "restart: the run that wrote the checkpoint had a stop_when, this one has none");
      const int ref = luaL_ref(L, LUA_REGISTRYINDEX);
      struct Unref {
        lua_State* L;
        int ref;
        ~Unref() { luaL_unref(L, LUA_REGISTRYINDEX, ref); }
      } unref{L, ref};
      call_lua(L, ref, s.self_ref, 1, "the run's stop_when");
      lua_pop(L, 1);
    } else {
      auto hook = s.lua_hooks.find(static_cast<int>(id));
      if (hook == s.lua_hooks.end())
        throw std::runtime_error(fmt::format(
            "restart: the checkpoint's journal fires hook {}, which this scene has not made", id));
      call_lua(L, hook->second.ref, s.self_ref, 0, hook->second.what);
    }
    after_callback = true;
  }
  return -1;
}

void begin_restart(SceneContext& ctx) {
  auto r = std::make_shared<Restart>();
  r->path = ctx.restart_path;
  r->state = std::make_unique<StateBlob>(io::read_checkpoint(ctx.restart_path));
  const StateBlob& st = *r->state;
  for (const char* key : {"lua.journal", "lua.overrides", "lua.scene_source"})
    if (!st.has(key))
      throw InputError(fmt::format(
          "checkpoint {}: no '{}' (written by an older granule, which kept no journal of the "
          "scene; rerun the scene to write a new checkpoint)",
          ctx.restart_path, key));
  if (st.has("lua.written_at") && st.t("lua.written_at") == "repl")
    throw InputError(fmt::format(
        "restart: {} was written at the granule repl prompt; its journal holds what was typed "
        "there, which no scene replays, so it cannot be continued (it keeps the state at that "
        "moment; a scene that does what the session did continues from its own checkpoints)",
        ctx.restart_path));
  // The same scene with the same parameters, or the past cannot be replayed.
  const auto recorded = parse_overrides(st.t("lua.overrides"));
  std::set<std::string> names;
  for (const auto& [k, v] : recorded) names.insert(k);
  for (const auto& [k, v] : ctx.overrides) names.insert(k);
  // A value given on one side only is the same run when it is the scene's
  // default, and two spellings of one number are one value (1e3 and 1000).
  auto same = [](const std::string& x, const std::string& y) {
    char *ex = nullptr, *ey = nullptr;
    const double dx = std::strtod(x.c_str(), &ex), dy = std::strtod(y.c_str(), &ey);
    return x == y || (!x.empty() && !y.empty() && *ex == 0 && *ey == 0 && dx == dy);
  };
  auto value_of = [&](const std::map<std::string, std::string>& given, const std::string& name,
                      std::string& out) {
    if (auto it = given.find(name); it != given.end()) return out = it->second, true;
    for (const ParameterDoc& d : ctx.parameter_docs)
      if (d.name == name) return out = d.default_value, true;
    return false;
  };
  for (const auto& name : names) {
    std::string value_then, value_now;
    if (value_of(recorded, name, value_then) && value_of(ctx.overrides, name, value_now) &&
        same(value_then, value_now))
      continue;
    auto a = recorded.find(name);
    auto b = ctx.overrides.find(name);
    const std::string was = a == recorded.end() ? "(not given)" : "-D " + name + "=" + a->second;
    const std::string now =
        b == ctx.overrides.end() ? "(not given)" : "-D " + name + "=" + b->second;
    if (was != now)
      throw InputError(fmt::format(
          "restart: parameter '{}' differs from the run that wrote {}: it had {}, this run has "
          "{}; a restart continues that run, so give it the same -D values",
          name, ctx.restart_path, was, now));
  }
  if (st.t("lua.scene_source") != ctx.scene_source)
    throw InputError(fmt::format(
        "restart: the scene {} changed since {} was written (from line {} on); a restart "
        "replays the scene that wrote the checkpoint",
        ctx.scene_path, ctx.restart_path,
        first_differing_line(st.t("lua.scene_source"), ctx.scene_source)));
  if (st.has("lua.modules")) {
    std::istringstream lines(st.t("lua.modules"));
    for (std::string line; std::getline(lines, line);) {
      const std::size_t space = line.find(' ');
      if (space == std::string::npos)
        throw InputError(fmt::format("checkpoint {}: 'lua.modules' is damaged", ctx.restart_path));
      const std::string digest = line.substr(0, space), file = line.substr(space + 1);
      std::ifstream in(file, std::ios::binary);
      const bool opened = in.is_open();
      std::stringstream text;
      if (opened) text << in.rdbuf();
      if (!opened || io::source_digest(text.str()) != digest)
        throw InputError(fmt::format(
            "restart: the module {} that the scene required {} since {} was written; a restart "
            "replays the code that wrote the checkpoint",
            file, opened ? "changed" : "is gone", ctx.restart_path));
    }
  }
  const auto& current = st.i("lua.current");
  if (current.size() != 3)
    throw InputError(fmt::format("checkpoint {}: 'lua.current' must hold 3 values, has {}",
                                 ctx.restart_path, current.size()));
  r->in_run = current[0] != 0;
  r->run_start_step = current[1];
  r->run_total_steps = current[2];
  if (st.has("lua.run_end_time")) {
    // {flag, end}, or {flag, end, dt} (the step the count was made with; 0 when
    // not saved: the step at the restart).
    const auto& end = st.d("lua.run_end_time");
    const bool sized = end.size() == 2 || end.size() == 3;
    if (!sized || (end[0] != 0 && !(std::isfinite(end[1]) && (end.size() == 2 || end[2] > 0))))
      throw InputError(fmt::format(
          "checkpoint {}: 'lua.run_end_time' is damaged (it must hold {{1, end time, time "
          "step}} for a run of a duration, {{0, 0, 0}} else)",
          ctx.restart_path));
    r->has_end_time = true;
    if (end[0] != 0) r->run_end_time = end[1], r->run_planned_dt = end.size() == 3 ? end[2] : 0;
  }
  if (r->in_run && (r->run_start_step < 0 || r->run_total_steps < 0))
    throw InputError(
        fmt::format("checkpoint {}: 'lua.current' holds a negative step", ctx.restart_path));
  const auto& output = st.i("lua.output");
  if (output.size() != 1 || output[0] < 0)
    throw InputError(fmt::format("checkpoint {}: 'lua.output' is damaged", ctx.restart_path));
  r->output_index = output[0];
  r->journal = st.b("lua.journal");
  // Checkpoints from before the journal kept the calls' argument digests have no format.
  if (st.has("lua.journal_format")) {
    const auto& format = st.i("lua.journal_format");
    if (format.size() != 1)
      throw InputError(
          fmt::format("checkpoint {}: 'lua.journal_format' is damaged", ctx.restart_path));
    r->journal_format = static_cast<int>(format[0]);
  }
  ctx.restart = r;
  SceneContext* c = &ctx;
  ctx.journal->start_replay(r->journal, r->journal_format, [c] { apply_restart(*c); });
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
    // A file named on the command line (--checkpoint, as granule sweep gives each
    // case its own) wins over the scene's, which every case of a sweep shares.
    if (!s.checkpoint_path_fixed) s.checkpoint.path = file;
    refuse_checkpoint_over(s, s.checkpoint.path);
    refuse_unwritable_checkpoint(s.checkpoint.path);
    s.checkpoint.every_steps = every_steps;
    s.checkpoint.every_seconds = every_seconds;
    // And a wall-clock period given there (--checkpoint-every) holds too: the sooner wins.
    if (const double cli = s.context ? s.context->checkpoint_every_seconds : 0; cli > 0)
      s.checkpoint.every_seconds = every_seconds > 0 ? std::min(every_seconds, cli) : cli;
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
