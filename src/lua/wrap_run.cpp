// Running a simulation: sim:run, the sim:every callbacks and the way every Lua
// callback is called (call_lua), sim:set and sim:prepare.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>

#include "core/errors.hpp"
#include "engine/run_loop.hpp"
#include "engine/simulation_base.hpp"
#include "io/run_output.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/run_progress.hpp"
#include "lua/scene.hpp"
#include "lua/wrap_simulation.hpp"

namespace granule::lua {

// The handler runs where the error was raised, before the stack unwinds: it names the
// callback, keeps the traceback of the callback's frames, and gives an error that is not
// a string (error({...}), error(nil)) the place it was raised.
int callback_error_handler(lua_State* L) {
  const char* what = lua_tostring(L, lua_upvalueindex(1));
  if (lua_type(L, 1) == LUA_TSTRING || lua_type(L, 1) == LUA_TNUMBER) {
    lua_pushfstring(L, "%s: %s", what, lua_tostring(L, 1));
  } else {
    push_script_where(L);
    const char* value = luaL_tolstring(L, 1, nullptr);
    lua_pushfstring(L, "%s raised a %s as its error (%s); raise a string: error(\"...\")", what,
                    luaL_typename(L, 1), value);
    lua_remove(L, -2);
    lua_concat(L, 2);
  }
  luaL_traceback(L, L, lua_tostring(L, -1), 1);
  return 1;
}

void call_lua(lua_State* L, int function_ref, int self_ref, int results, const std::string& what) {
  lua_pushlstring(L, what.data(), what.size());
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
}  // namespace

int l_run(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running)
      throw std::runtime_error("run: cannot run a simulation from inside its own callback");
    // A -D that nothing reads: refused before the run, not after it (run_file checks
    // again at the end, for a scene that never runs).
    if (SceneContext* ctx = context(L); ctx && !ctx->parameters_declared && !ctx->overrides.empty())
      throw std::runtime_error(fmt::format(
          "run: -D {} given, but the scene declares no parameters{{...}} (before its first run)",
          ctx->overrides.begin()->first));
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
    // Under mpirun each particle's sums are taken in id order, whichever rank holds it.
    if (ctx && ctx->spread) s.sim->set_canonical_order(true);
    s.sim->ensure_prepared();
    // The run's header: what this scene simulates (and so what it pays for).
    if (first_run && !(ctx && ctx->quiet)) {
      for (const auto& line : s.sim->describe()) std::cerr << "granule: " << line << "\n";
      s.header_printed = true;
    }
    // This run's effects beside the earlier runs', from the whole scene (before it is
    // spread over ranks); a resumed run's were noted before its checkpoint.
    if (s.output && !resuming) s.output->note_effects();
    // An output opened after the scene had stepped records the state this run
    // starts from, as one opened at t = 0 records step 0's (RunOutput).
    if (s.output && !resuming) s.output->record_opening();
    // Under mpirun the steps are spread over the ranks (engine/spread_run.hpp);
    // the scene is whole again on every rank when a callback, a stop check or
    // a checkpoint looks at it, and when the run ends.
    std::unique_ptr<SpreadRun> spread;
    if (ctx && ctx->spread) {
      spread = ctx->spread(*s.sim);
      const ActiveEffects e = s.sim->effects();
      if (first_run && !ctx->quiet) std::cerr << "granule: " << e.decomposition << "\n";
      // The ranks of this run (a restart may continue a file other ranks began).
      if (s.output) {
        s.output->file().write_attribute("/scene/effects", "ranks", std::int64_t{e.ranks});
        s.output->file().write_attribute("/scene/effects", "decomposition", e.decomposition);
      }
    }
    const double dt = s.sim->time_step();
    if (resuming) {
      steps = s.run_total_steps;
      // Where the run was to end (a checkpoint of an older build holds none: then
      // as its steps left at the step it had then).
      const Restart& r = *ctx->restart;
      s.run_end_time = !has_duration    ? std::numeric_limits<double>::quiet_NaN()
                       : r.has_end_time ? r.run_end_time
                                        : s.sim->time() + static_cast<double>(steps - done) * dt;
      s.run_planned_dt = r.run_planned_dt > 0 ? r.run_planned_dt : dt;
    } else {
      if (has_duration) {
        // A step count beyond 2^62 would overflow the counters (and never finish).
        const double n = steps_to_cover(duration, dt);
        if (!(n < 4.6e18))
          throw std::runtime_error(
              fmt::format("run: duration = {} s is {:.3g} steps of dt = {} s, too many to count",
                          duration, n, dt));
        steps = static_cast<std::int64_t>(std::max(0.0, n));
      }
      s.run_start_step = s.sim->step_count();
      s.run_total_steps = steps;
      s.run_end_time =
          has_duration ? s.sim->time() + duration : std::numeric_limits<double>::quiet_NaN();
      s.run_planned_dt = dt;
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
                       stop_ref != LUA_NOREF, RunProgress::Clock{}, delay, 0.25,
                       ctx->progress_log ? RunProgress::Style::log : RunProgress::Style::terminal,
                       ctx->progress_every);
      if (done > 0) progress->continued_after(done);
    }
    // The engine's runner takes the steps; the scene's criterion, its checkpoints and the
    // user's interrupt are served between its chunks.
    RunHooks hooks;
    hooks.stop_when = [&] {
      if (journal) journal->record_callback(-1);
      // Spread over ranks: the shares kept unless the criterion reads more
      // than the totals (SpreadRun::run_script).
      auto call = [&] { call_lua(L, stop_ref, s.self_ref, 1, "the run's stop_when"); };
      if (spread)
        spread->run_script(call);
      else
        call();
      bool stop = lua_toboolean(L, -1);
      lua_pop(L, 1);
      // Ranks whose criteria disagree (one reading the wall clock) stop together,
      // when any of them says so: one rank stepping on alone would wait forever.
      if (spread) stop = spread->any(stop);
      return stop;
    };
    hooks.write_checkpoint = [&](const std::string& path) {
      if (!spread) {
        write_checkpoint_now(s, path, true);
        return;
      }
      // Every rank writes (rank 0 where named, the others into scratch): one
      // that fails alone (a full disk) ends them all (settle).
      spread->gather();
      std::exception_ptr error;
      try {
        write_checkpoint_now(s, path, true);
      } catch (...) {
        error = std::current_exception();
      }
      spread->settle(error);
    };
    if (spread) {
      hooks.advance = [&](std::int64_t n) { spread->advance(n); };
      hooks.any = [&](bool mine) { return spread->any(mine); };
      hooks.agreed = [&](std::int64_t mine) { return spread->agreed(mine); };
    }
    // Spread over ranks, a signal that reached some ranks only stops every rank, each
    // naming that signal (its exit status too), not the Ctrl-C it would assume.
    hooks.interrupt_pending = [&] {
      const bool mine = interrupt_pending();
      if (!spread) return mine;
      const std::int64_t signal_number = spread->largest(mine ? interrupt_signal() : 0);
      if (signal_number > 0 && !mine) request_interrupt(static_cast<int>(signal_number));
      return signal_number > 0;
    };
    if (progress) hooks.progress = [&](std::int64_t n, double time) { progress->update(n, time); };
    std::int64_t chunks_taken = 0;
    if (s.output) {
      hooks.between_chunks = [&] {
        if (!spread) {
          s.output->flush_if_due();
          return;
        }
        // A flush that fails on some ranks only (rank 0's disk full) ends them all at
        // once, as a checkpoint's does, rather than leave the others in the next step:
        // at every 8th chunk (every rank takes the same chunks), so that runs whose
        // chunks are single steps (a stop check each step) meet no more often.
        if (++chunks_taken % 8 != 0) return;
        std::exception_ptr error;
        try {
          s.output->flush_if_due();
        } catch (...) {
          error = std::current_exception();
        }
        spread->settle(error);
      };
    }
    std::string interrupt_path = s.checkpoint.path;
    const bool at_prompt = ctx && ctx->repl;
    if (interrupt_path.empty() && at_prompt) {
      // At the REPL's prompt: beside the output the session writes (-o), where it is found.
      const std::string out = s.output ? s.output->path() : ctx->output_path;
      if (!out.empty()) {
        const std::filesystem::path p(out);
        interrupt_path = (p.parent_path() / (p.stem().string() + ".checkpoint.h5")).string();
      }
    }
    if (interrupt_path.empty()) interrupt_path = interrupt_checkpoint_path(s);
    // Before any step: a checkpoint, periodic or at a signal, never over the output.
    if (!s.checkpoint.path.empty()) {
      refuse_checkpoint_over(s, s.checkpoint.path);
      refuse_unwritable_checkpoint(s.checkpoint.path);
    }
    refuse_checkpoint_over(s, interrupt_path);
    RunPlan plan;
    plan.steps = steps;
    plan.done = done;
    plan.check_every = stop_ref != LUA_NOREF ? check_every : 0;
    plan.end_time = s.run_end_time;
    plan.planned_dt = s.run_planned_dt;
    hooks.retarget = [&](std::int64_t total, double counted_with) {
      s.run_total_steps = total;  // what a checkpoint from here on records
      s.run_planned_dt = counted_with;
      if (progress) progress->retarget(total - done);
    };
    RunOutcome outcome;
    {
      struct Active {
        Active() { set_run_active(true); }
        ~Active() { set_run_active(false); }
      } active;
      outcome = run_in_chunks(*s.sim, plan, s.checkpoint, interrupt_path, hooks);
    }
    if (spread) {
      spread->gather();
      // Every rank takes part (the other ranks are always quiet).
      const std::string lines = spread->timing();
      if (ctx && !ctx->quiet && ctx->rank == 0) std::cerr << lines;
      spread.reset();
    }
    done = outcome.done;
    steps = outcome.steps;
    const bool stopped = outcome.stopped;
    if (outcome.interrupted) {
      // Between two steps, with the checkpoint written: say where and how to go on.
      lua_sethook(L, nullptr, 0, 0);  // the hook the signal also set, to stop script loops
      clear_interrupt();
      if (progress) progress->finish();
      if (at_prompt) {
        // Not an error at the prompt: the user stopped to look, and goes on from here.
        std::cerr << fmt::format(
            "run interrupted at t = {} s (step {}, {} of {} steps), state kept; checkpoint "
            "written to {}\n",
            s.sim->time(), s.sim->step_count(), done, steps, interrupt_path);
      } else {
        std::string message = fmt::format(
            "run interrupted ({}) after {} of {} steps, at t = {} s (step {}){}", interrupt_cause(),
            done, steps, s.sim->time(), s.sim->step_count(), continue_hint(ctx, interrupt_path));
        if (ctx) ctx->interrupted = true, ctx->interrupt_message = message;
        throw std::runtime_error(message);
      }
    }
    if (progress) progress->finish();
    if (s.output && !outcome.interrupted) s.output->end_of_run();
    lua_newtable(L);
    lua_pushinteger(L, done);
    lua_setfield(L, -2, "steps");
    lua_pushnumber(L, s.sim->time());
    lua_setfield(L, -2, "time");
    lua_pushboolean(L, stopped);
    lua_setfield(L, -2, "stopped");
    lua_pushboolean(L, outcome.interrupted);
    lua_setfield(L, -2, "interrupted");
    return 1;
  });
}

// every { steps = N | time = T, function(sim) ... end } -> hook id
int l_every(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    TableReader t(L, 2, "every");
    Hook h;
    h.script = true;
    h.name = t.string("name", "lua callback");
    h.every_steps = t.integer("steps", 0);
    h.every_time = t.number("time", 0);
    if (h.every_steps < 0 || h.every_time < 0)
      throw std::runtime_error("every: steps and time must be > 0");
    if ((h.every_steps > 0) == (h.every_time > 0))
      throw std::runtime_error("every: give exactly one of steps = N (> 0) or time = T [s] (> 0)");
    t.finish();
    if (lua_rawgeti(L, 2, 1) != LUA_TFUNCTION) {
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
    // Its name in an error: the hook id, for sim:remove_hook (a callback that
    // fails stays registered, and fails again in the next run at the prompt).
    auto what = std::make_shared<std::string>();
    h.fire = [L, ref, self_ref, journal, id, what] {
      if (journal && !journal->replaying()) journal->record_callback(*id);
      call_lua(L, ref, self_ref, 0, *what);
    };
    *id = s.sim->add_hook(h);
    *what = fmt::format("sim:every callback '{}' (hook {}: sim:remove_hook({}) removes it)", h.name,
                        *id, *id);
    s.lua_hooks[*id] = {ref, *what};
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
    // The function goes from the registry too (a script adding and removing
    // callbacks in a loop would otherwise keep every one alive).
    if (auto hook = s.lua_hooks.find(static_cast<int>(id)); hook != s.lua_hooks.end()) {
      luaL_unref(L, LUA_REGISTRYINDEX, hook->second.ref);
      s.lua_hooks.erase(hook);
    }
    return 0;
  });
}

// sim:set { skin =, time_step =, steps_per_contact =, threads =, pruning =, canonical_order = }:
// change numerical settings between runs (the next run re-checks the scene and rebuilds its
// lists).
int l_set(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    if (s.running) throw std::runtime_error("set: not from inside a run's callback");
    TableReader t(L, 2, "set");
    if (t.has("skin")) s.sim->set_skin(t.number("skin"));
    if (t.has("time_step")) s.sim->set_time_step(t.number("time_step"));
    if (t.has("steps_per_contact")) s.sim->set_steps_per_contact(t.number("steps_per_contact"));
    if (t.has("threads")) s.sim->set_threads(t.integer("threads"));
    if (t.has("pruning")) s.sim->set_pruning(t.boolean("pruning", true));
    if (t.has("canonical_order")) s.sim->set_canonical_order(t.boolean("canonical_order", false));
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

}  // namespace granule::lua
