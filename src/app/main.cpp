// granule: the command-line front end.
//   granule run scene.lua [-D name=value ...] [-o out.h5] [--quiet]
//   granule repl [scene.lua] [-D ...]
//   granule sweep scene.lua -D name=v1,v2 ... [-o DIR]   (app/sweep.hpp)
//   granule models          list contact models and their parameters
//   granule api [NAME | --markdown]   the Lua API reference
//   granule api --models-markdown PAGE   PAGE with its model parameter tables regenerated
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <lua.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "app/interrupt.hpp"
#include "app/repl.hpp"
#include "app/sweep.hpp"
#include "contact/model_docs.hpp"
#include "contact/models.hpp"
#include "io/h5_output.hpp"
#include "io/rank_files.hpp"
#include "lua/api_docs.hpp"
#include "lua/journal.hpp"
#include "lua/run_progress.hpp"
#include "lua/scene.hpp"

#ifdef GRANULE_HAVE_MPI
#include <mpi.h>

#include <filesystem>

#include "parallel/gathering.hpp"
#include "parallel/scene_over_ranks.hpp"
#endif

namespace {

const char* usage =
    "usage:\n"
    "  granule run SCENE.lua [-D name=value ...] [-o OUT.h5] [--quiet] [--threads N]\n"
    "              [--restart CHECKPOINT.h5] [--checkpoint FILE.h5] [--checkpoint-every SECONDS]\n"
    "              [--progress SECONDS]\n"
    "  granule run SCENE.lua --help   the scene's parameters: defaults, units, docs\n"
    "  granule repl [SCENE.lua] [-D name=value ...] [-o OUT.h5] [--quiet] [--threads N]\n"
    "  granule sweep SCENE.lua -D name=v1,v2,... [-D ...] [-o DIR] [--threads N] [-q]\n"
    "              [--case-timeout SECONDS] [--checkpoint-every SECONDS] [--list]\n"
    "  granule models\n"
    "  granule api [NAME | --markdown | --models-markdown docs/contact_models.md]\n"
    "  granule --version\n"
    "options:\n"
    "  -D name=value   override a parameter the scene declares (repeatable)\n"
    "  -o OUT.h5       output file (an OUT.xmf for ParaView is written beside it)\n"
    "  -q, --quiet     no run header, warnings or progress line\n"
    "  --progress S    a progress line every S seconds of wall time once a run has taken\n"
    "                  2 s, each a line of its own (without it: on a terminal one line\n"
    "                  redrawn in place; otherwise a line at every tenth of a run that\n"
    "                  lasts over 2 s)\n"
    "  --checkpoint FILE.h5      where the run's checkpoints go (periodic, and on a signal)\n"
    "  --checkpoint-every S      a checkpoint every S seconds of wall time\n";

// A failed scene's report: its error, the same text on every rank that failed
// alike, and what rank 0 alone adds (the files kept, the signal's exit status).
struct FailureReport {
  std::string error, extra;
};

struct Options {
  std::string command, scene;
  granule::lua::SceneContext ctx;
  // Under mpirun the report waits until the ranks have met, so that an error every
  // rank raised is printed once (run_scene_over_ranks); otherwise run_scene prints it.
  bool hold_report = false;
  FailureReport report;
};

std::string rank_prefix(const Options& o) {
  return o.ctx.ranks > 1 ? fmt::format("granule: rank {} of {}: ", o.ctx.rank, o.ctx.ranks) : "";
}

int fail_usage(const std::string& message) {
  std::cerr << "granule: " << message << "\n" << usage;
  return 2;
}

// -D name=value; returns an error message, or "" when it was recorded.
std::string add_override(Options& o, const std::string& v) {
  auto eq = v.find('=');
  if (eq == std::string::npos || eq == 0) return "-D expects name=value, got '" + v + "'";
  std::string name = v.substr(0, eq);
  if (o.ctx.overrides.count(name)) return "-D " + name + " given twice";
  o.ctx.overrides[name] = v.substr(eq + 1);
  return "";
}

// On ranks other than 0 a scene's own files (io.open for writing, os.remove,
// os.rename) go to the rank's scratch folder, as the engine's do (io/rank_files.hpp),
// and a file read (io.open, io.lines) is the rank's own copy where it wrote one
// (a scene that writes a file and reads it back); its standard output goes nowhere: rank
// 0 writes and prints for all.
int rank_path_call(lua_State* L) {
  const int n = lua_gettop(L);
  const int kind = static_cast<int>(lua_tointeger(L, lua_upvalueindex(2)));  // Wrapped::kind
  const char* mode = n >= 2 && lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "r";
  // io.open(path, mode): its path, written or read; io.lines(path): read;
  // os.remove(path), os.rename(from, to): every path, written.
  const bool opens = kind != 0;
  const bool writes = kind == 0 || kind == 3 || (kind == 1 && std::strpbrk(mode, "wa+"));
  const int paths = opens ? std::min(n, 1) : n;
  for (int k = 1; k <= paths; ++k)
    if (lua_type(L, k) == LUA_TSTRING) {
      const std::string named = lua_tostring(L, k);
      const std::string mapped =
          writes ? granule::io::writable_path(named) : granule::io::readable_path(named);
      lua_pushstring(L, mapped.c_str());
      lua_replace(L, k);
    }
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  return lua_gettop(L);
}

void keep_files_on_rank(lua_State* L) {
  // What the scene prints (print, io.write, sim:table, a plotting script's
  // lines) rank 0 prints for all: this rank's standard output goes nowhere.
  if (!std::freopen("/dev/null", "w", stdout))
    throw std::runtime_error("rank's standard output cannot be closed");
  // os.tmpname's files in the rank's scratch folder, which goes at exit (a
  // scene's os.remove of one goes to its scratch copy, and would leave it).
  lua_getglobal(L, "os");
  if (lua_istable(L, -1)) {
    lua_getfield(L, -1, "tmpname");
    lua_pushcclosure(
        L,
        [](lua_State* S) {
          const std::string name = granule::io::scratch_temporary();
          if (name.empty()) {  // no scratch folder: the library's own
            lua_pushvalue(S, lua_upvalueindex(1));
            lua_call(S, 0, 1);
            return 1;
          }
          lua_pushstring(S, name.c_str());
          return 1;
        },
        1);
    // Journaled as rank 0's is (journal_clocks): a restart replays one journal.
    granule::lua::push_journaled(L, "os.tmpname", granule::lua::Journal::Kind::observe);
    lua_setfield(L, -2, "tmpname");
  }
  lua_pop(L, 1);
  struct Wrapped {
    const char *library, *name;
    int kind;  // rank_path_call: 0 every argument written, 1 io.open, 2 read (io.lines,
               // io.input), 3 written (io.output)
  };
  for (const Wrapped w :
       {Wrapped{"io", "open", 1}, Wrapped{"io", "lines", 2}, Wrapped{"io", "input", 2},
        Wrapped{"io", "output", 3}, Wrapped{"os", "remove", 0}, Wrapped{"os", "rename", 0}}) {
    lua_getglobal(L, w.library);
    if (!lua_istable(L, -1)) {
      lua_pop(L, 1);
      continue;
    }
    lua_getfield(L, -1, w.name);
    lua_pushinteger(L, w.kind);
    lua_pushcclosure(L, rank_path_call, 2);
    lua_setfield(L, -2, w.name);
    lua_pop(L, 1);
  }
}

int run_scene(Options& o) {
  lua_State* L = granule::lua::new_state(&o.ctx);
  granule::lua::clear_progress_before_prints(L);
  if (o.ctx.rank > 0) keep_files_on_rank(L);
  granule::lua::make_globals_strict(L);
  std::string err;
  {
    granule::app::InterruptScope interrupt(L);
    err = granule::lua::run_file(L, o.scene);
  }
  // A file the scene leaves open on an error says so (RunOutput::note_scene_error); a
  // stopped run's file is continued by its restart, which must find it as it was.
  if (!err.empty() && !o.ctx.interrupted) o.ctx.scene_error = err;
  lua_close(L);  // closes output files (their final snapshot) even after an error
  // A restart that could not take over failed the scene wherever the journal ended
  // (inside a callback, or a call the scene caught): say so as the restart's error.
  if (!o.ctx.restart_failure.empty()) err = o.ctx.restart_failure;
  // A scene that caught its stop (pcall) and ended still ends as stopped.
  if (err.empty() && o.ctx.interrupted)
    err = o.ctx.interrupt_message + " (the scene caught the stop and ended)";
  if (!err.empty()) {
    FailureReport& report = o.report;
    report = {"error: " + err + "\n", ""};
    std::vector<std::string> shown;  // a scene may reopen one file many times
    // Rank 0 names the files kept; the other ranks' copies go with their scratch.
    if (o.ctx.rank == 0)
      for (const auto& f : o.ctx.outputs_written)
        if (std::find(shown.begin(), shown.end(), f) == shown.end()) {
          report.extra += (o.ctx.outputs_finished.count(f) ? "complete results kept in "
                                                           : "partial results kept in ") +
                          f + "\n";
          shown.push_back(f);
        }
    int status = 1;
    if (o.ctx.interrupted) {
      // 128 + the signal, as a shell reports a program it ended: 130 Ctrl-C, 143 SIGTERM,
      // 129 SIGHUP; a scheduler or `granule sweep` reads the cause from the status.
      status = 128 + granule::lua::interrupt_signal();
      report.extra += fmt::format("granule: stopped by {} (exit status {})\n",
                                  granule::lua::interrupt_cause(), status);
    }
    // One write: ranks failing together must not interleave their lines.
    if (!o.hold_report) std::cerr << rank_prefix(o) + report.error + report.extra << std::flush;
    return status;
  }
  return 0;
}

// granule run SCENE --help: the scene runs as far as its parameters{...} (as `granule
// sweep` checks a case), which lists what -D can set.
int scene_help(Options& o) {
  o.ctx.parameters_only = true;
  o.ctx.quiet = true;
  lua_State* L = granule::lua::new_state(&o.ctx);
  lua_pushcfunction(L, [](lua_State*) { return 0; });  // what it prints on the way: not help
  lua_setglobal(L, "print");
  granule::lua::make_globals_strict(L);
  const std::string err = granule::lua::run_file(L, o.scene);
  lua_close(L);
  if (!o.ctx.stopped_after_parameters && !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return 1;
  }
  auto docs = o.ctx.parameter_docs;
  if (docs.empty()) {
    // The scene ran as far as its simulation{...}: parameters declared after it
    // are not seen here (nor by granule sweep), though run -D still sets them.
    std::cout << o.scene
              << " declares no parameters{...} before its simulation{...}, which is as far as "
                 "--help reads (declare them first to have them listed and swept)\n";
    return 0;
  }
  std::sort(docs.begin(), docs.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::size_t name_w = 4, value_w = 7, unit_w = 4;
  for (const auto& d : docs) {
    name_w = std::max(name_w, d.name.size());
    value_w = std::max(value_w, d.default_value.size());
    unit_w = std::max(unit_w, d.unit.size() + 2);
  }
  std::cout << "parameters of " << o.scene << " (set with -D name=value):\n";
  std::cout << fmt::format("  {:<{}}  {:<{}}  {:<{}}  {}\n", "name", name_w, "default", value_w,
                           "unit", unit_w, "meaning");
  for (const auto& d : docs) {
    std::string line =
        fmt::format("  {:<{}}  {:<{}}  {:<{}}  {}", d.name, name_w, d.default_value, value_w,
                    d.unit.empty() ? "" : "[" + d.unit + "]", unit_w, d.doc);
    line.erase(line.find_last_not_of(' ') + 1);
    std::cout << line << "\n";
  }
  return 0;
}

int list_models() {
  std::cout << granule::format_models_help();
  return 0;
}

int api(const std::vector<std::string>& args) {
  if (args.size() == 3 && args[1] == "--models-markdown") {  // docs/contact_models.md
    std::cout << granule::regenerate_model_tables_in(args[2]);
    return 0;
  }
  if (args.size() > 2) return fail_usage("api takes at most one name");
  if (args.size() == 1) {
    std::cout << granule::lua::format_overview();
    return 0;
  }
  if (args[1] == "--markdown") {
    std::cout << granule::lua::api_markdown();
    return 0;
  }
  const granule::lua::FunctionDoc* d = granule::lua::find_doc(args[1]);
  if (!d) {
    std::string hint = granule::lua::nearest_doc_name(args[1]);
    std::cerr << "granule: nothing in the API is called '" << args[1] << "'"
              << (hint.empty() ? "" : " (did you mean '" + hint + "'?)")
              << "; `granule api` lists every name\n";
    return 2;
  }
  std::cout << granule::lua::format_help(*d);
  return 0;
}

int run_command(const std::vector<std::string>& args);

#ifdef GRANULE_HAVE_MPI
// mpirun -np N granule run SCENE.lua: every rank runs the script; each run's
// steps are spread over the ranks (parallel/scene_over_ranks.hpp). Rank 0
// prints, and writes the files; the others write into scratch folders of their own.
// This process as one of the ranks a scene is spread over: rank 0 writes the
// files and prints; the others write into a scratch folder of their own.
// Where the ranks meet at their end (run_scene_over_ranks).
MPI_Comm exit_comm = MPI_COMM_NULL;

void join_ranks(Options& o) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &o.ctx.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &o.ctx.ranks);
  o.ctx.spread = granule::parallel::spread_over(MPI_COMM_WORLD);
  MPI_Comm_dup(MPI_COMM_WORLD, &exit_comm);
  o.ctx.all_ranks = [](bool mine) {
    int in = mine ? 1 : 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return out != 0;
  };
  if (o.ctx.rank > 0) {
    o.ctx.quiet = true;
    o.ctx.progress = false;
    const std::filesystem::path temp = std::filesystem::temp_directory_path();
    granule::io::remove_stale_scratch(temp.string(), "granule-rank");
    granule::io::write_files_into(
        (temp / fmt::format("granule-rank{}-{}", o.ctx.rank, static_cast<long>(getpid())))
            .string());
  }
}

// The ranks' reports, once they have all met: rank 0 prints each distinct error once,
// naming the ranks that raised it, then its own files and status.
void print_reports_together(const Options& o) {
  // Each report as "<failed 0/1><error>\0" (a NUL in the error's text read as a space).
  std::string error = o.report.error;
  std::replace(error.begin(), error.end(), '\0', ' ');
  const std::string mine = (error.empty() ? "0" : "1") + error + std::string(1, '\0');
  const std::string all = granule::parallel::all_gather(mine, exit_comm);
  if (o.ctx.rank != 0) return;
  std::vector<std::pair<std::string, std::vector<int>>> errors;  // in order of first rank
  std::size_t at = 0;
  for (int rank = 0; rank < o.ctx.ranks; ++rank) {
    const std::size_t end = all.find('\0', at);
    const std::string report = all.substr(at, end - at);
    at = end + 1;
    if (report.empty() || report[0] == '0') continue;
    const std::string error = report.substr(1);
    auto same =
        std::find_if(errors.begin(), errors.end(), [&](const auto& e) { return e.first == error; });
    if (same == errors.end())
      errors.push_back({error, {rank}});
    else
      same->second.push_back(rank);
  }
  std::string message;
  for (const auto& [error, ranks] : errors) {
    if (static_cast<int>(ranks.size()) == o.ctx.ranks)
      message += fmt::format("granule: all {} ranks: {}", o.ctx.ranks, error);
    else
      message += fmt::format("granule: rank{} {} of {}: {}", ranks.size() > 1 ? "s" : "",
                             fmt::join(ranks, ", "), o.ctx.ranks, error);
  }
  std::cerr << message + o.report.extra << std::flush;
}

int run_scene_over_ranks(Options& o) {
  join_ranks(o);
  o.hold_report = true;
  const int status = run_scene(o);
  granule::io::remove_scratch();
  // Every rank meets here at its end. A scene that fails alike on every rank (an
  // error before its first run) ends each with its status, its error printed once;
  // a rank that failed alone (the others still step, or wait for it in a run) ends
  // them all, with its status, when the others have not come within 20 s (rank 0 may
  // still be closing its files).
  // (On a communicator of its own: it must not meet a run's collectives.)
  MPI_Request met;
  MPI_Ibarrier(exit_comm, &met);
  if (status == 0) {
    MPI_Wait(&met, MPI_STATUS_IGNORE);
  } else {
    int all_here = 0;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!all_here && std::chrono::steady_clock::now() < until) {
      MPI_Test(&met, &all_here, MPI_STATUS_IGNORE);
      if (!all_here) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (!all_here) {
      std::cerr << rank_prefix(o) + o.report.error + o.report.extra << std::flush;
      MPI_Abort(MPI_COMM_WORLD, status);
    }
  }
  // Every rank is here: a failure is known to all; the reports meet at rank 0.
  int failed = status != 0 ? 1 : 0, any_failed = 0;
  MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, exit_comm);
  if (any_failed) print_reports_together(o);
  MPI_Comm_free(&exit_comm);
  MPI_Finalize();
  return status;
}

// The REPL over the ranks: rank 0 reads each line (standard input, which
// mpirun gives rank 0) and hands it to every rank, so every rank runs the same
// chunks and the scene's runs spread as under `granule run`. What the prompt
// prints (values, a chunk's error) is printed by rank 0; the others' standard
// output goes nowhere. A chunk's error is every rank's alike and ends nothing;
// an error on some ranks only ends every rank (the spread run's abandon).
int repl_over_ranks(Options& o) {
  join_ranks(o);
  const bool root = o.ctx.rank == 0;
  granule::app::ReplInput input = granule::app::terminal_input();
  int interactive = root && input.interactive ? 1 : 0;
  MPI_Bcast(&interactive, 1, MPI_INT, 0, MPI_COMM_WORLD);
  input.interactive = interactive != 0;
  if (!root) input.prepare = keep_files_on_rank;
  input.read = [root](const char* prompt, std::string& line) {
    std::int64_t size = -1;  // -1: end of input
    if (root && granule::app::read_terminal_line(prompt, line))
      size = static_cast<std::int64_t>(line.size());
    MPI_Bcast(&size, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
    if (size < 0) return false;
    line.resize(static_cast<std::size_t>(size));
    MPI_Bcast(line.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD);
    return true;
  };
  const int status = granule::app::run_repl(o.scene, o.ctx, input);
  granule::io::remove_scratch();
  MPI_Finalize();
  return status;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  // Whatever escapes (out of memory, a Lua state that cannot be made) ends
  // with a message and status 1, never with an abort.
  granule::io::keep_hdf5_files_at_exit();
  // Standard output closed by its reader (`granule run ... | head`) must not end
  // a run and lose its checkpoint: the prints fail quietly, the run and its
  // HDF5 output go on.
  std::signal(SIGPIPE, SIG_IGN);
  // A file size limit (ulimit -f) reached by a write must come back as an error
  // (EFBIG) that the output reports and records, not kill the run unannounced.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    return run_command(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const std::exception& e) {
    std::cerr << "granule: error: " << e.what() << "\n";
    return 1;
  }
}

namespace {

int run_command(const std::vector<std::string>& args) {
  if (args.empty()) return fail_usage("no command given");
  Options o;
  o.command = args[0];
  const bool bare =
      o.command == "--version" || o.command == "--help" || o.command == "-h" || o.command == "help";
  if (bare && args.size() > 1) return fail_usage(o.command + " takes no arguments");
  if (o.command == "--version") {
    // The commit is the source tree's at configure time (git describe --always --dirty).
    std::cout << "granule " << GRANULE_VERSION << " (commit " << GRANULE_COMMIT << ")\n";
    return 0;
  }
  if (o.command == "--help" || o.command == "-h" || o.command == "help") {
    std::cout << usage;
    return 0;
  }
  // `granule COMMAND --help` (without a scene): the usage, as `granule --help`.
  const bool known =
      o.command == "run" || o.command == "repl" || o.command == "models" || o.command == "api";
  if (known && args.size() == 2 && (args[1] == "--help" || args[1] == "-h")) {
    std::cout << usage;
    return 0;
  }
  if (o.command == "models") {
    if (args.size() > 1) return fail_usage("models takes no arguments");
    return list_models();
  }
  if (o.command == "api") return api(args);
  if (o.command == "sweep") return granule::app::run_sweep({args.begin() + 1, args.end()});
  if (o.command != "run" && o.command != "repl")
    return fail_usage("unknown command '" + o.command + "'");
  // Started by mpirun (granule sweep's cases are started without the
  // launcher's variables, so they are not): the scene is spread over the ranks.
  int launched_ranks = 0;
  const char* launcher_variable = nullptr;
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* value = std::getenv(variable); value && std::atoi(value) > 0) {
      launched_ranks = std::atoi(value);
      launcher_variable = variable;
      break;
    }
#ifdef GRANULE_HAVE_MPI
  (void)launcher_variable;
#else
  if (launched_ranks > 1) {
    std::cerr << "granule: error: " << o.command << " started as one of " << launched_ranks
              << " MPI ranks (" << launcher_variable
              << "), but this build has no MPI: every rank would run the whole scene and write "
                 "the same files (install libopenmpi-dev and build again)\n";
    return 2;
  }
#endif
  bool scene_help_asked = false;
  for (std::size_t k = 1; k < args.size(); ++k) {
    const std::string& a = args[k];
    if (a == "-D" || a == "-o") {
      if (k + 1 >= args.size()) return fail_usage(a + " needs a value");
      const std::string& v = args[++k];
      if (a == "-o") {
        if (v.empty()) return fail_usage("-o needs a file name");
        if (v[0] == '-')
          return fail_usage("-o needs a file name, got the option '" + v +
                            "' (a file whose name starts with '-': ./" + v + ")");
        if (!o.ctx.output_path.empty()) return fail_usage("-o given twice");
        o.ctx.output_path = v;
      } else if (std::string err = add_override(o, v); !err.empty()) {
        return fail_usage(err);
      }
    } else if (a.rfind("-D", 0) == 0 && a.size() > 2) {
      if (std::string err = add_override(o, a.substr(2)); !err.empty()) return fail_usage(err);
    } else if (a == "--quiet" || a == "-q") {
      o.ctx.quiet = true;
    } else if (a == "--restart") {
      if (k + 1 >= args.size()) return fail_usage("--restart needs a checkpoint file");
      o.ctx.restart_path = args[++k];
    } else if (a == "--checkpoint") {
      if (k + 1 >= args.size() || args[k + 1].empty())
        return fail_usage("--checkpoint needs a file name");
      o.ctx.checkpoint_path = args[++k];
    } else if (a == "--checkpoint-every") {
      if (k + 1 >= args.size()) return fail_usage("--checkpoint-every needs a value");
      const std::string& v = args[++k];
      char* end = nullptr;
      const double t = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != 0 || !(t > 0) || !std::isfinite(t))
        return fail_usage("--checkpoint-every expects seconds of wall time > 0, got '" + v + "'");
      o.ctx.checkpoint_every_seconds = t;
    } else if (a == "--help" || a == "-h") {
      scene_help_asked = true;
    } else if (a == "--progress") {
      if (k + 1 >= args.size()) return fail_usage("--progress needs a value");
      const std::string& v = args[++k];
      char* end = nullptr;
      const double t = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != 0 || !(t > 0) || !std::isfinite(t))
        return fail_usage("--progress expects seconds of wall time > 0, got '" + v + "'");
      o.ctx.progress_every = t;
    } else if (a == "--threads") {
      if (k + 1 >= args.size()) return fail_usage("--threads needs a value");
      const std::string& v = args[++k];
      char* end = nullptr;
      long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != 0 || n < 1 || n > 4096)
        return fail_usage("--threads expects a whole number from 1 to 4096, got '" + v + "'");
      o.ctx.threads = static_cast<int>(n);
    } else if (!a.empty() && a[0] == '-') {
      return fail_usage("unknown option '" + a + "'");
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      return fail_usage("more than one scene file given ('" + o.scene + "', '" + a + "')");
    }
  }

  if (!o.ctx.restart_path.empty() && o.command != "run")
    return fail_usage("--restart goes with run SCENE.lua (a checkpoint continues a scene file)");
  o.ctx.scene_path = o.scene;
  // On a terminal the progress line rewrites itself with \r; in a batch log (stderr a
  // file or a pipe) it is a line every tenth of the run, or every --progress seconds.
  o.ctx.progress = !o.ctx.quiet || o.ctx.progress_every > 0;
  o.ctx.progress_log = !isatty(2) || o.ctx.progress_every > 0;
  if (scene_help_asked) {  // run or repl SCENE --help: the scene's parameters
    if (o.scene.empty()) return fail_usage("--help with other options goes with a scene file");
    return scene_help(o);
  }
  if (o.command == "run") {
    if (o.scene.empty()) return fail_usage("run needs a scene file");
#ifdef GRANULE_HAVE_MPI
    if (launched_ranks > 0) return run_scene_over_ranks(o);
#endif
    return run_scene(o);
  }
  // A scene that cannot be read is a mistake in the command, not a session to open
  // bare (a scene that fails part-way does open: its `sim` can be looked at).
  if (!o.scene.empty()) {
    std::error_code ec;
    if (!std::filesystem::exists(o.scene, ec))
      return fail_usage("cannot open scene file '" + o.scene + "'");
    if (std::filesystem::is_directory(o.scene, ec))
      return fail_usage("'" + o.scene + "' is a directory, not a scene file");
  } else if (!o.ctx.overrides.empty()) {
    return fail_usage(
        "-D sets a scene's parameter: give the scene (granule repl SCENE.lua -D ...)");
  }
#ifdef GRANULE_HAVE_MPI
  if (launched_ranks > 0) return repl_over_ranks(o);
#endif
  return granule::app::run_repl(o.scene, o.ctx);
}

}  // namespace
