#include "app/sweep.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <lua.hpp>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "app/sweep_child.hpp"
#include "app/sweep_ranks.hpp"
#include "app/sweep_summary.hpp"
#include "app/sweep_types.hpp"
#include "io/case_record.hpp"
#include "io/h5_output.hpp"
#include "lua/scene.hpp"

namespace granule::app {

namespace {

namespace fs = std::filesystem;

const char* sweep_usage =
    "usage: granule sweep SCENE.lua -D name=v1,v2,... [-D name=value ...] [-o DIR]\n"
    "                     [--threads N] [-q] [--case-timeout SECONDS] [--checkpoint-every "
    "SECONDS]\n"
    "                     [--list]\n"
    "  runs every combination of the listed values, one `granule run` per case;\n"
    "  under mpirun the cases are shared among the ranks (see docs/performance.md)\n";

using namespace sweep_detail;  // the shared types (sweep_types.hpp)

// flock() on DIR/.granule-sweep.lock for the sweep's life (the kernel drops it
// when the process ends, however it ends); throws naming the folder when
// another process holds it. An empty folder: no lock (a worker rank).
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::string& directory) {
    if (directory.empty()) return;
    const std::string path = (fs::path(directory) / ".granule-sweep.lock").string();
    fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw std::runtime_error(
          fmt::format("cannot make the lock file {}: {}", path, strerror(errno)));
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int why = errno;
      close(fd_);
      fd_ = -1;
      if (why == EWOULDBLOCK)
        throw std::runtime_error(fmt::format(
            "another granule sweep is writing into {}/ (it holds {}); wait for it to end, or "
            "give this one another folder (-o)",
            directory, path));
      // A filesystem without flock (some network mounts): go on unlocked.
    }
  }
  ~DirectoryLock() {
    if (fd_ >= 0) close(fd_);
  }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

// Loads the scene with this case's values as far as its parameters{...}, in this
// process: a name the scene does not declare, or a value of the wrong kind, is
// refused before any case runs, with the same message `granule run` gives.
std::string check_parameters(const Settings& s, const Case& c,
                             std::map<std::string, std::string>* units = nullptr) {
  lua::SceneContext ctx;
  ctx.scene_path = s.scene;
  ctx.quiet = true;
  ctx.parameters_only = true;
  for (const auto& [name, value] : c.values) ctx.overrides[name] = value;
  lua_State* L = lua::new_state(&ctx);
  // What a scene prints before its parameters{...} would appear once per case: not here.
  lua_pushcfunction(L, [](lua_State*) { return 0; });
  lua_setglobal(L, "print");
  lua::make_globals_strict(L);
  std::string err = lua::run_file(L, s.scene);
  lua_close(L);
  if (units)
    for (const auto& d : ctx.parameter_docs) (*units)[d.name] = d.unit;
  if (ctx.stopped_after_parameters) {
    if (ctx.declared_parameters.empty() && !c.values.empty())
      return fmt::format(
          "-D {}: the scene declares no parameters{{...}} before its simulation{{...}} (a sweep "
          "sets only parameters declared before it)",
          c.values.front().first);
    return "";
  }
  return err;
}

// ---- the summary ----

std::string describe(const Case& c) {
  std::string text;
  for (const auto& [name, value] : c.values) text += (text.empty() ? "" : " ") + name + "=" + value;
  return text.empty() ? "(defaults)" : text;
}

// ---- the sweep ----

int sweep(const Settings& given, Ranks& ranks) {
  const bool lead = ranks.rank() == 0;
  Settings s = given;
  std::vector<Case> cases = make_cases(s);
  for (const Case& c : cases) {
    std::string err = check_parameters(s, c, &s.parameter_units);
    if (!err.empty()) {
      if (lead) std::cerr << "granule sweep: " << err.substr(0, err.find('\n')) << "\n";
      return 2;
    }
  }
  if (s.list_only) {
    if (lead)
      for (const Case& c : cases) {
        auto record = io::read_case_record(c.file);
        const bool same_case = record && record->key == c.key;
        const bool finished = same_case && record->scene_digest == s.scene_digest;
        std::error_code ec;
        const bool resumable = !finished && fs::exists(c.checkpoint, ec);
        std::cout << fmt::format("{} {} -> {}{}\n", c.index, describe(c), c.file,
                                 finished    ? " (finished)"
                                 : same_case ? " (finished by another version of the scene: runs "
                                               "again)"
                                 : resumable ? " (continues from " + c.checkpoint + ")"
                                             : "");
      }
    return 0;
  }
  std::error_code ec;
  fs::create_directories(s.directory, ec);
  if (!fs::is_directory(s.directory, ec)) {
    if (lead)
      std::cerr << "granule sweep: cannot make the output directory '" << s.directory << "'\n";
    return 2;
  }
  // One sweep at a time in a folder: a second would truncate the files the
  // first is writing (HDF5's own locks are off: they fail on shared filesystems).
  const DirectoryLock lock(lead ? s.directory : std::string());
  // Several ranks on one node share its cores unless told otherwise (--threads, or
  // OMP_NUM_THREADS, which the cases then read themselves).
  int threads = s.threads;
  if (threads == 0 && ranks.per_node() > 1 && !std::getenv("OMP_NUM_THREADS"))
    threads = std::max(1, int(std::thread::hardware_concurrency()) / ranks.per_node());

  // SIGTERM and SIGHUP (a scheduler ending the job, a closed terminal) stop the sweep as
  // Ctrl-C does: the running cases get the signal, write their checkpoints and stop, and
  // the summary records what finished.
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGHUP, on_stop_signal);
#ifdef GRANULE_HAVE_MPI
  if (!lead) {  // a worker: ask for cases until there are none
    std::string report;
    for (long long index; (index = ranks.ask(report)) >= 0;)
      report = encode(run_case(s, cases[std::size_t(index)], threads, ranks.rank()));
    return 0;
  }
#endif

  std::vector<Outcome> outcomes(cases.size());
  std::vector<std::size_t> queue;
  std::size_t reused = 0;
  for (const Case& c : cases) {
    Outcome& o = outcomes[c.index];
    o.index = c.index;
    // Finished by this scene as it is now: a case of an edited scene runs again.
    auto record = io::read_case_record(c.file);
    if (record && record->key == c.key && record->scene_digest == s.scene_digest) {
      o.status = Status::reused;
      o.rank = record->rank;
      o.wall_seconds = record->wall_seconds;
      try {
        o.results = io::read_results(c.file);
      } catch (const std::exception&) {
      }
      ++reused;
    } else {
      queue.push_back(c.index);
    }
  }
  std::reverse(queue.begin(), queue.end());  // pop_back hands out case 0 first
  std::cout << fmt::format(
                   "sweep: {} case{} of {} ({} finished earlier), {} rank{}, output in {}/\n",
                   cases.size(), cases.size() == 1 ? "" : "s", s.scene, reused, ranks.size(),
                   ranks.size() == 1 ? "" : "s", s.directory)
            << std::flush;

  std::size_t done = reused;
  auto record = [&](Outcome o) {
    if (o.status == Status::interrupted && !stop_signal)
      stop_signal = o.stop_signal ? o.stop_signal : SIGINT;
    ++done;
    const Case& c = cases[o.index];
    std::string line =
        fmt::format("[{}/{}] {}: {}", done, cases.size(), describe(c), status_name(o.status));
    if (o.status == Status::ok)
      line += fmt::format(" ({:.1f} s, rank {}{})", o.wall_seconds, o.rank,
                          o.continued ? ", continued from its checkpoint" : "");
    if (!o.error.empty()) line += ": " + o.error + " (log: " + c.log + ")";
    if (o.status != Status::ok)
      std::cerr << line << "\n";
    else if (!s.quiet)
      std::cout << line << "\n" << std::flush;
    outcomes[o.index] = std::move(o);
  };

  std::unique_ptr<RunningCase> own;
  int workers = ranks.size() - 1;
  // Polls the workers and its own case, waiting from 1 ms up to 50 ms while nothing happens.
  for (int wait_ms = 1; workers > 0 || own || (!queue.empty() && !stop_signal);) {
    bool busy = false;
#ifdef GRANULE_HAVE_MPI
    int from = 0;
    std::string report;
    while (workers > 0 && ranks.take_request(from, report)) {
      busy = true;
      if (!report.empty()) record(decode(report));
      if (!queue.empty() && !stop_signal) {
        ranks.assign(from, static_cast<long long>(queue.back()));
        queue.pop_back();
      } else {
        ranks.assign(from, -1);
        --workers;
      }
    }
#endif
    if (own) {
      Outcome o;
      if (own->poll(o)) {
        own.reset();
        record(std::move(o));
        busy = true;
      }
    }
    if (!own && !queue.empty() && !stop_signal) {
      const Case& c = cases[queue.back()];
      queue.pop_back();
      own = std::make_unique<RunningCase>(s, c, threads, ranks.rank());
      busy = true;
    }
    wait_ms = busy ? 1 : std::min(2 * wait_ms, 50);
    if (!busy) std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
  }

  std::vector<std::string> result_names;
  Summary table = tabulate(s, cases, outcomes, result_names);
  const std::string base = (fs::path(s.directory) / fs::path(s.scene).stem()).string() + ".sweep";
  write_csv(base + ".csv", table);
  write_markdown(base + ".md", s, table);
  std::ifstream csv(base + ".csv");
  std::stringstream csv_text;
  csv_text << csv.rdbuf();
  bool h5_written = true;
  try {
    write_h5(base + ".h5", s, cases, outcomes, result_names, csv_text.str());
  } catch (const std::exception& e) {
    std::cerr << "granule sweep: the HDF5 summary was not written: " << e.what() << "\n";
    h5_written = false;
  }
  std::map<Status, std::size_t> count;
  for (const auto& o : outcomes) ++count[o.status];
  std::size_t finished = count[Status::ok] + count[Status::reused];
  std::cout << fmt::format(
                   "sweep: {} of {} cases finished ({} now, {} earlier), {} failed{}; "
                   "summary in {}.{}\n",
                   finished, cases.size(), count[Status::ok], count[Status::reused],
                   count[Status::failed],
                   finished + count[Status::failed] < cases.size() ? ", stopped early" : "", base,
                   h5_written ? "{csv,md,h5}" : "{csv,md} (not .h5: see above)")
            << std::flush;
  if (stop_signal) return 128 + stop_signal;  // as a shell reports a run ended by the signal
  return finished == cases.size() && h5_written ? 0 : 1;
}

}  // namespace

int run_sweep(const std::vector<std::string>& args) {
  for (const std::string& a : args)
    if (a == "--help" || a == "-h") {
      std::cout << sweep_usage;
      return 0;
    }
  Settings settings;
  try {
    settings = parse(args);
  } catch (const UsageError& e) {
    // Under a launcher every rank finds the same mistake: one message is enough.
    const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
    if (!rank) rank = std::getenv("PMI_RANK");
    if (!rank || std::atoi(rank) == 0)
      std::cerr << "granule sweep: " << e.what() << "\n" << sweep_usage;
    return 2;
  }
  {
    std::ifstream scene(settings.scene, std::ios::binary);
    std::stringstream text;
    text << scene.rdbuf();
    settings.scene_digest = io::source_digest(text.str());
  }
  Ranks ranks;
  if (ranks.idle()) return 0;
  try {
    return sweep(settings, ranks);
  } catch (const std::exception& e) {
    std::cerr << "granule sweep: error: " << e.what() << "\n";
    ranks.abort();
    return 1;
  }
}

}  // namespace granule::app
