// Running a scene file: a Lua state with the Granule API, strict globals,
// -D parameter overrides, and one protected call with a traceback so every
// error reaches the user with its file and line.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/spread_run.hpp"

struct lua_State;

namespace granule::lua {

class Journal;
struct Restart;
struct LuaSim;

// A parameter as parameters{...} declares it, for `granule run SCENE --help`.
struct ParameterDoc {
  std::string name, default_value, unit, doc;
};

struct SceneContext {
  std::string scene_path;
  std::string scene_source;
  // The Lua files the scene loaded with require: path and io::source_digest of the text
  // loaded, which a restart checks as it checks the scene's own source.
  std::vector<std::pair<std::string, std::string>> module_sources;
  std::string output_path;  // from -o; empty = the scene's own choice or <scene>.h5
  // sim:output calls -o has named so far: the first takes -o's path, each later
  // one -o's stem and its own file's (a scene writing two files, in a sweep).
  int outputs_under_o = 0;
  std::map<std::string, std::string> overrides;  // -D name=value
  std::set<std::string> consumed;
  bool parameters_declared = false;
  std::vector<std::pair<std::string, std::string>> parameter_values;  // for provenance
  std::map<std::string, double> numeric_parameters;
  std::map<std::string, std::int64_t> integer_parameters;  // those declared integer = true
  bool quiet = false;
  int threads = 0;           // --threads N: overrides every simulation's own setting when > 0
  std::string restart_path;  // --restart FILE: the first simulation continues this checkpoint
  // --checkpoint FILE [--checkpoint-every SECONDS]: where the first simulation's
  // checkpoints go (periodic ones, and the one a signal writes), whatever file the
  // scene names, and how often by wall time when the scene asks for none.
  std::string checkpoint_path;
  double checkpoint_every_seconds = 0;
  bool checkpoint_assigned = false;   // the first simulation has taken checkpoint_path
  bool interrupted = false;           // a run stopped on a signal (the program exits with 128 + it)
  std::string interrupt_message;      // how it stopped: every later engine call raises it again
  bool views_read_in_replay = false;  // sim:arrays() read NaN while a restart replayed (warned)
  // The scene's first simulation (while it lives): a signal while the scene's
  // own Lua code runs, between runs, checkpoints it (checkpoint_between_runs).
  LuaSim* first_simulation = nullptr;
  bool progress = false;      // progress line for long runs (the CLI: unless --quiet)
  bool progress_log = false;  // as lines of their own (stderr is not a terminal, or --progress)
  double progress_every = 0;  // --progress S: a line every S s of wall time; 0: every 10 %
  // granule repl: the output stays open until the session ends (sim:close() only flushes)
  // and Ctrl-C stops a run without an error, keeping its state for the prompt.
  bool repl = false;
  bool repl_prompt = false;  // the REPL has begun to journal what is typed at its prompt
  std::vector<std::string> outputs_written;
  // Of those, the ones the scene finished (a later sim:output, sim:close) before an
  // error: complete, where the one still open then holds the results up to the error.
  std::set<std::string> outputs_finished;
  // The error the scene ended on (not a stop by signal), set before its
  // simulations close: each open output records it as its `failure` attribute.
  std::string scene_error;
  std::shared_ptr<Journal> journal;    // what the scene saw of the engine (journal.hpp)
  std::shared_ptr<Restart> restart;    // --restart: the checkpoint being continued
  std::function<void()> begin_replay;  // run before the scene's first journaled call
  // Why the checkpoint's state could not be taken over at the journal's end: the
  // scene's error whatever call or callback it surfaced in, and every later call
  // fails with it (a pcall in the scene must not run on from a state half restored).
  std::string restart_failure;
  // `granule sweep` checks each case's -D values against the scene before running any:
  // parameters{...} validates the overrides, records the declared names and then stops
  // the scene; so does simulation{...}, should a scene make one before (or without)
  // declaring its parameters.
  bool parameters_only = false;
  std::vector<std::string> declared_parameters;
  std::vector<ParameterDoc> parameter_docs;  // every parameters{...} entry, in declaration order
  bool stopped_after_parameters = false;
  // Under mpirun: this process's rank among `ranks`, and the maker of the runs
  // that spread the scene over them (app/main.cpp; empty on one process).
  int rank = 0, ranks = 1;
  SpreadRunMaker spread;
  // Whether every rank says true (MPI_Allreduce; empty on one process): all ranks
  // pass it, whatever each says, so that none waits for a rank that failed.
  std::function<bool(bool)> all_ranks;
};

// The message parameters{...} stops a scene with when SceneContext::parameters_only is set.
inline constexpr const char* parameters_checked_stop = "parameters checked (granule sweep)";

// Ctrl-C, SIGTERM and SIGHUP (what `timeout` and batch schedulers send). The
// signal handler only records the signal (async-signal-safe); sim:run checks
// it between chunks of steps and ends with an error naming the step.
void request_interrupt(int signal_number);
bool interrupt_pending();
void clear_interrupt();
// Whether sim:run is taking steps: then an interrupt is served between two chunks of
// steps, and the signal handler must not also stop the Lua code of a callback midway
// (a callback cut short would leave the scene in a state no uninterrupted run reaches).
void set_run_active(bool active);
bool run_active();
// The signal of the latest request (SIGINT when none came), kept after
// clear_interrupt() so that the message written after the checkpoint can name it.
int interrupt_signal();
// "Ctrl-C", "SIGTERM" or "SIGHUP": the latest request's signal, for messages.
const char* interrupt_cause();

// A fresh state with the standard libraries, the granule API and lua/ on package.path.
lua_State* new_state(SceneContext* context);
// Makes reading or writing an undeclared global an error.
void make_globals_strict(lua_State* L);
// Loads and runs a file in protected mode; returns "" or the error with traceback.
std::string run_file(lua_State* L, const std::string& path);
// Runs a string chunk (the REPL); returns "" or the error.
std::string run_string(lua_State* L, const std::string& chunk, const std::string& chunk_name);

// Registers simulation{...}, simulations() and the methods (lua_simulation.cpp).
void open_simulation(lua_State* L);
SceneContext* context(lua_State* L);
// A restart is replaying the scene's past (journal.hpp): checks made against the
// engine's time are the first run's, which it passed at its own time.
bool replaying(lua_State* L);

// A signal stopped the scene's own Lua code between runs: writes the first
// simulation's checkpoint where a run's signal would have (the scene is whole
// and between steps), and returns "; checkpoint written to ...; continue
// with: ..." for the message, or "" where none is written (at the REPL's
// prompt, while a restart replays, spread over ranks, no simulation yet).
// Throws when the checkpoint cannot be written (wrap_checkpoint.cpp).
std::string checkpoint_between_runs(SceneContext& ctx);
// Where a stopped run of `s` writes its checkpoint outside the REPL: the
// scene's or the command line's checkpoint file, else <scene>.checkpoint.h5.
std::string interrupt_checkpoint_path(const LuaSim& s);
// "; checkpoint written to P; continue with: granule run SCENE -D ... --restart P".
std::string continue_hint(const SceneContext* ctx, const std::string& checkpoint);
// --restart: whether the checkpoint's state has taken over (the scene's journal reached
// its end; wrap_checkpoint.cpp).
bool restart_applied(const SceneContext& ctx);

}  // namespace granule::lua
