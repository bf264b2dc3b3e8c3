#include "app/sweep.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/syscall.h>
#include <sys/wait.h>
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

#include "app/sweep_summary.hpp"
#include "app/sweep_types.hpp"
#include "io/case_record.hpp"
#include "io/h5_output.hpp"
#include "lua/scene.hpp"

#ifdef GRANULE_HAVE_MPI
#include <mpi.h>
#endif

extern char** environ;

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

// Loads the scene with this case's values as far as its parameters{...}, in this
// process: a name the scene does not declare, or a value of the wrong kind, is
// refused before any case runs, with the same message `granule run` gives.
std::string check_parameters(const Settings& s, const Case& c) {
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
  if (ctx.stopped_after_parameters) {
    if (ctx.declared_parameters.empty() && !c.values.empty())
      return fmt::format(
          "-D {}: the scene makes its simulation before declaring any parameters{{...}}",
          c.values.front().first);
    return "";
  }
  return err;
}

// ---- running one case ----

volatile std::sig_atomic_t stop_signal = 0;

void on_stop_signal(int signal) {
  stop_signal = signal;
}

std::string self_executable() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the granule program (/proc/self/exe)");
  return p.string();
}

// The first line of the error the run printed ("error: ..." from the scene, "granule:
// error: ..." from the program), else its last line.
std::string error_from_log(const std::string& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    for (const char* prefix : {"error: ", "granule: error: "})
      if (line.rfind(prefix, 0) == 0) return line.substr(std::strlen(prefix));
    if (!line.empty()) last = line;
  }
  return last;
}

class RunningCase {
 public:
  RunningCase(const Settings& s, const Case& c, int threads, int rank)
      : case_(c), rank_(rank), timeout_(s.case_timeout), start_(std::chrono::steady_clock::now()) {
    std::vector<std::string> args{self_executable(), "run", s.scene};
    for (const auto& [name, value] : c.values) args.insert(args.end(), {"-D", name + "=" + value});
    args.insert(args.end(), {"-o", c.file});
    // A case stopped half-way (a signal, a lost node, the sweep killed) left its
    // checkpoint: it goes on from there, its output file continued, its log appended.
    std::error_code ec;
    const bool resume = fs::exists(c.checkpoint, ec);
    continued_ = resume;
    if (resume) args.insert(args.end(), {"--restart", c.checkpoint});
    args.insert(args.end(), {"--checkpoint", c.checkpoint});
    if (s.checkpoint_every > 0)
      args.insert(args.end(), {"--checkpoint-every", fmt::format("{:g}", s.checkpoint_every)});
    if (threads > 0) args.insert(args.end(), {"--threads", std::to_string(threads)});
    if (s.quiet) args.push_back("-q");
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // The case is a plain `granule run`: it must not take itself for an MPI rank, so the
    // launcher's variables stay behind. Everything is prepared before fork(): an MPI rank
    // has threads of its own, and the child may only make async-signal-safe calls.
    std::vector<char*> env;
    for (char** e = environ; *e; ++e)
      if (std::strncmp(*e, "OMPI_", 5) != 0 && std::strncmp(*e, "PMIX_", 5) != 0 &&
          std::strncmp(*e, "PMI_", 4) != 0)
        env.push_back(*e);
    env.push_back(nullptr);
    const char* log = c.log.c_str();
    std::string exec_error = std::string("error: cannot run ") + argv[0] + "\n";
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error(std::string("cannot start a case: ") + strerror(errno));
    if (pid_ == 0) {
      int fd = open(log, O_WRONLY | O_CREAT | (resume ? O_APPEND : O_TRUNC), 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        close(fd);
      }
      // Nothing of the rank's (MPI sockets, shared memory) stays open in the case.
#ifdef SYS_close_range
      if (syscall(SYS_close_range, 3U, ~0U, 0U) != 0)
#endif
        for (int other = 3; other < 1024; ++other) close(other);
      signal(SIGINT, SIG_DFL);
      signal(SIGTERM, SIG_DFL);
      signal(SIGHUP, SIG_DFL);
      execve(argv[0], argv.data(), env.data());
      ssize_t ignored = write(2, exec_error.data(), exec_error.size());
      (void)ignored;
      _exit(127);
    }
  }

  // Polls; returns true once the case has ended (the outcome is then filled in).
  bool poll(Outcome& out) {
    if (stop_signal && !forwarded_) {
      // Under a launcher the signal reaches the rank, not its child: pass it on.
      kill(pid_, stop_signal);
      forwarded_ = true;
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (timeout_ > 0 && elapsed > timeout_ && !timed_out_) {
      kill(pid_, SIGTERM);
      timed_out_ = true;
    } else if (timed_out_ && elapsed > timeout_ + 10) {
      kill(pid_, SIGKILL);  // ten seconds after SIGTERM
    }
    int status = 0;
    pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == 0 || (r < 0 && errno == EINTR)) return false;
    out.index = case_.index;
    out.rank = rank_;
    out.wall_seconds = elapsed;
    out.continued = continued_;
    if (r < 0) {
      out.status = Status::failed;
      out.error = std::string("lost the case's process: ") + strerror(errno);
    } else if (timed_out_ && !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
      out.status = Status::failed;
      out.error = fmt::format("stopped after {:g} s (--case-timeout)", timeout_);
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      finish(out);
    } else if (WIFSIGNALED(status)) {
      out.status = forwarded_ ? Status::interrupted : Status::failed;
      out.error =
          fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
    } else {
      int code = WEXITSTATUS(status);
      // A case stopped by a signal of its own (a scheduler signals the whole process
      // group) exits 128 + that signal, with its checkpoint written.
      const bool stopped = code == 128 + SIGINT || code == 128 + SIGTERM || code == 128 + SIGHUP;
      out.status = (stopped || forwarded_) ? Status::interrupted : Status::failed;
      if (stopped) out.stop_signal = code - 128;
      out.error = error_from_log(case_.log);
      if (out.error.empty()) out.error = fmt::format("exit status {}", code);
    }
    return true;
  }

 private:
  void finish(Outcome& out) {
    try {
      std::error_code ec;
      if (fs::exists(case_.file, ec)) out.results = io::read_results(case_.file);
      io::CaseRecord record;
      record.key = case_.key;
      record.rank = rank_;
      record.wall_seconds = out.wall_seconds;
      io::write_case_record(case_.file, record);
      out.status = Status::ok;
      // Finished: its checkpoint would only make a later sweep continue a done case.
      fs::remove(case_.checkpoint, ec);
    } catch (const std::exception& e) {
      out.status = Status::failed;
      out.error = e.what();
    }
  }

  Case case_;
  int rank_;
  double timeout_;
  std::chrono::steady_clock::time_point start_;
  pid_t pid_ = -1;
  bool forwarded_ = false, timed_out_ = false, continued_ = false;
};

#ifdef GRANULE_HAVE_MPI
// A worker rank runs its cases one at a time, waiting on each.
Outcome run_case(const Settings& s, const Case& c, int threads, int rank) {
  Outcome out;
  out.index = c.index;
  out.rank = rank;
  if (stop_signal) return out;  // not run
  RunningCase running(s, c, threads, rank);
  for (int wait_ms = 1; !running.poll(out); wait_ms = std::min(2 * wait_ms, 50))
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
  return out;
}

// ---- messages between ranks ----

std::string clean_line(std::string text) {
  std::replace(text.begin(), text.end(), '\t', ' ');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

std::string encode(const Outcome& o) {
  std::string text = fmt::format("{}\t{}\t{}\t{:.17g}\t{}\t{}\n", o.index, int(o.status), o.rank,
                                 o.wall_seconds, o.continued ? 1 : 0, clean_line(o.error));
  for (const auto& [name, value] : o.results) text += fmt::format("{}\t{:.17g}\n", name, value);
  return text;
}

Outcome decode(const std::string& text) {
  Outcome o;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::istringstream head(line);
  std::string field;
  std::getline(head, field, '\t');
  o.index = std::stoul(field);
  std::getline(head, field, '\t');
  o.status = static_cast<Status>(std::stoi(field));
  std::getline(head, field, '\t');
  o.rank = std::stoi(field);
  std::getline(head, field, '\t');
  o.wall_seconds = std::stod(field);
  std::getline(head, field, '\t');
  o.continued = field == "1";
  std::getline(head, o.error);
  while (std::getline(in, line)) {
    auto tab = line.find('\t');
    if (tab != std::string::npos) o.results[line.substr(0, tab)] = std::stod(line.substr(tab + 1));
  }
  return o;
}

#endif  // GRANULE_HAVE_MPI

// MPI when the program was started by a launcher (mpirun, mpiexec); otherwise none, so
// that a plain `granule sweep` never waits on an MPI start-up it does not need.
class Ranks {
 public:
  Ranks() {
#ifdef GRANULE_HAVE_MPI
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") ||
        std::getenv("PMI_RANK")) {
      MPI_Init(nullptr, nullptr);
      active_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
      MPI_Comm node;
      MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
      MPI_Comm_size(node, &node_size_);
      MPI_Comm_free(&node);
    }
#else
    // Started by a launcher but built without MPI: every rank would run every case into the
    // same files. The first runs them all; the others leave at once.
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
      if (const char* r = std::getenv(name); r && std::atoi(r) > 0) {
        idle_ = true;
        return;
      }
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"))
      std::cerr << "granule sweep: this granule was built without MPI; rank 0 runs every case\n";
#endif
  }
  ~Ranks() {
#ifdef GRANULE_HAVE_MPI
    if (active_) MPI_Finalize();
#endif
  }
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;
  int rank() const {
    return rank_;
  }
  int size() const {
    return size_;
  }
  int per_node() const {
    return node_size_;
  }
  bool idle() const {  // a rank with nothing to do (a launcher, but built without MPI)
    return idle_;
  }
  // After an error on one rank: the others may be waiting on it, so end them all.
  void abort() const {
#ifdef GRANULE_HAVE_MPI
    if (active_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, 1);
#endif
  }

#ifdef GRANULE_HAVE_MPI
  static constexpr int tag_request = 1, tag_assign = 2;
  // Worker: reports the last outcome (empty at first) and gets the next case, or -1.
  long long ask(const std::string& report) const {
    MPI_Send(report.data(), static_cast<int>(report.size()), MPI_CHAR, 0, tag_request,
             MPI_COMM_WORLD);
    long long index = -1;
    MPI_Recv(&index, 1, MPI_LONG_LONG, 0, tag_assign, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return index;
  }
  // Rank 0: a worker's request if one is waiting: its rank and report.
  bool take_request(int& from, std::string& report) const {
    int waiting = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, tag_request, MPI_COMM_WORLD, &waiting, &status);
    if (!waiting) return false;
    int length = 0;
    MPI_Get_count(&status, MPI_CHAR, &length);
    report.assign(static_cast<std::size_t>(length), '\0');
    MPI_Recv(report.data(), length, MPI_CHAR, status.MPI_SOURCE, tag_request, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    from = status.MPI_SOURCE;
    return true;
  }
  void assign(int to, long long index) const {
    MPI_Send(&index, 1, MPI_LONG_LONG, to, tag_assign, MPI_COMM_WORLD);
  }
#endif

 private:
  bool active_ = false, idle_ = false;
  int rank_ = 0, size_ = 1, node_size_ = 1;
};

// ---- the summary ----

std::string describe(const Case& c) {
  std::string text;
  for (const auto& [name, value] : c.values) text += (text.empty() ? "" : " ") + name + "=" + value;
  return text.empty() ? "(defaults)" : text;
}

// ---- the sweep ----

int sweep(const Settings& s, Ranks& ranks) {
  const bool lead = ranks.rank() == 0;
  std::vector<Case> cases = make_cases(s);
  for (const Case& c : cases) {
    std::string err = check_parameters(s, c);
    if (!err.empty()) {
      if (lead) std::cerr << "granule sweep: " << err.substr(0, err.find('\n')) << "\n";
      return 2;
    }
  }
  if (s.list_only) {
    if (lead)
      for (const Case& c : cases) {
        auto record = io::read_case_record(c.file);
        bool finished = record && record->key == c.key;
        std::error_code ec;
        const bool resumable = !finished && fs::exists(c.checkpoint, ec);
        std::cout << fmt::format("{} {} -> {}{}\n", c.index, describe(c), c.file,
                                 finished    ? " (finished)"
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
    auto record = io::read_case_record(c.file);
    if (record && record->key == c.key) {
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
  try {
    write_h5(base + ".h5", s, cases, outcomes, result_names, csv_text.str());
  } catch (const std::exception& e) {
    std::cerr << "granule sweep: the HDF5 summary was not written: " << e.what() << "\n";
  }
  std::map<Status, std::size_t> count;
  for (const auto& o : outcomes) ++count[o.status];
  std::size_t finished = count[Status::ok] + count[Status::reused];
  std::cout << fmt::format(
                   "sweep: {} of {} cases finished ({} now, {} earlier), {} failed{}; "
                   "summary in {}.{{csv,md,h5}}\n",
                   finished, cases.size(), count[Status::ok], count[Status::reused],
                   count[Status::failed],
                   finished + count[Status::failed] < cases.size() ? ", stopped early" : "", base)
            << std::flush;
  if (stop_signal) return 128 + stop_signal;  // as a shell reports a run ended by the signal
  return finished == cases.size() ? 0 : 1;
}

}  // namespace

int run_sweep(const std::vector<std::string>& args) {
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
