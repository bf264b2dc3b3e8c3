#include "app/sweep_child.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "io/case_record.hpp"
#include "io/checkpoint.hpp"
#include "io/h5_output.hpp"

extern char** environ;

namespace granule::app::sweep_detail {

namespace fs = std::filesystem;

volatile std::sig_atomic_t stop_signal = 0;

void on_stop_signal(int signal) {
  stop_signal = signal;
}

namespace {

std::string self_executable() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the granule program (/proc/self/exe)");
  return p.string();
}

// The first line of the error the run ended on ("error: ..." from the scene, "granule:
// error: ..." from the program): the last such line of the log, as the program reports
// its error after everything the scene printed (which may hold such lines of its
// own); else the log's last line. From byte `start` on (a continued case appends to
// the log of its earlier attempts).
std::string error_from_log(const std::string& log, std::uintmax_t start) {
  std::ifstream in(log);
  in.seekg(static_cast<std::streamoff>(start));
  std::string line, last, error;
  while (std::getline(in, line)) {
    for (const char* prefix : {"error: ", "granule: error: "})
      if (line.rfind(prefix, 0) == 0) error = line.substr(std::strlen(prefix));
    if (!line.empty()) last = line;
  }
  return error.empty() ? last : error;
}

// Why an earlier sweep's checkpoint of this case's file names cannot be
// continued by this case (empty: it can): it was written with other -D values
// (the values an earlier sweep held fixed, or another case that had this
// file's name) or by another version of the scene. A restart would refuse it
// each time the sweep runs.
std::string foreign_checkpoint(const std::string& path, const Case& c, const std::string& digest) {
  std::string values;  // as the run records them: name=value lines in name order
  std::map<std::string, std::string> sorted(c.values.begin(), c.values.end());
  for (const auto& [name, value] : sorted) values += name + "=" + value + "\n";
  try {
    if (io::read_checkpoint_text(path, "lua.overrides") != values)
      return "it was written with other -D values";
    if (io::source_digest(io::read_checkpoint_text(path, "lua.scene_source")) != digest)
      return "it was written by another version of the scene";
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// The wall time of a case's earlier parts, kept beside its checkpoint
// (`<checkpoint>.wall_s`: seconds of the parts before, and when this part
// began, in seconds since the epoch). A part that ended without the sweep
// seeing it (the sweep killed, a lost node) counts up to its last checkpoint,
// the state the next part goes on from.
std::string earlier_parts_file(const Case& c) {
  return c.checkpoint + ".wall_s";
}

double epoch_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double earlier_parts_seconds(const Case& c) {
  std::ifstream in(earlier_parts_file(c));
  double before = 0, began = 0;
  struct stat st {};
  if (!(in >> before >> began) || stat(c.checkpoint.c_str(), &st) != 0) return 0;
  const double written = double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec);
  return std::max(0.0, before) + std::max(0.0, written - began);
}

void note_part_start(const Case& c, double before) {
  std::ofstream out(earlier_parts_file(c), std::ios::trunc);
  out << fmt::format("{:.17g} {:.17g}\n", before, epoch_seconds());
}

}  // namespace

RunningCase::RunningCase(const Settings& s, const Case& c, int threads, int rank)
    : case_(c),
      scene_digest_(s.scene_digest),
      rank_(rank),
      timeout_(s.case_timeout),
      start_(std::chrono::steady_clock::now()) {
  std::vector<std::string> args{self_executable(), "run", s.scene};
  for (const auto& [name, value] : c.values) args.insert(args.end(), {"-D", name + "=" + value});
  args.insert(args.end(), {"-o", c.file});
  // A case stopped half-way (a signal, a lost node, the sweep killed) left its
  // checkpoint: it goes on from there, its output file continued, its log appended.
  std::error_code ec;
  bool resume = fs::exists(c.checkpoint, ec);
  if (resume) {
    const std::string why = foreign_checkpoint(c.checkpoint, c, s.scene_digest);
    if (!why.empty()) {
      // Kept for whoever wants it, out of the way of this case's own.
      const std::string aside = c.checkpoint + ".set-aside";
      fs::rename(c.checkpoint, aside, ec);
      std::cerr << fmt::format(
          "granule sweep: case {}: not continuing {} ({}); moved to {}, the "
          "case runs from its start\n",
          c.index, c.checkpoint, why, aside);
      resume = false;
    }
  }
  continued_ = resume;
  earlier_seconds_ = resume ? earlier_parts_seconds(c) : 0;
  note_part_start(c, earlier_seconds_);
  log_start_ = resume ? fs::file_size(c.log, ec) : 0;
  if (ec) log_start_ = 0;
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
  const pid_t parent = getpid();
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error(std::string("cannot start a case: ") + strerror(errno));
  if (pid_ == 0) {
    // A sweep killed outright (SIGKILL, a lost node) leaves no case running on
    // as an orphan beside a rerun of the sweep: the case gets SIGTERM, writes
    // its checkpoint and ends.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(128 + SIGTERM);
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
    // The sweep's own program, through /proc/self/exe rather than its path: a
    // rebuild that replaces the file while a study runs (its path then reads
    // "... (deleted)") must neither fail the cases still to start nor run them
    // on another build than the cases before them.
    execve("/proc/self/exe", argv.data(), env.data());
    ssize_t ignored = write(2, exec_error.data(), exec_error.size());
    (void)ignored;
    _exit(127);
  }
}

bool RunningCase::poll(Outcome& out) {
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
  out.wall_seconds = earlier_seconds_ + elapsed;
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
    out.error = error_from_log(case_.log, log_start_);
    if (out.error.empty()) out.error = fmt::format("exit status {}", code);
  }
  std::error_code ec;
  if (!fs::exists(case_.checkpoint, ec)) fs::remove(earlier_parts_file(case_), ec);
  return true;
}

void RunningCase::finish(Outcome& out) {
  try {
    std::error_code ec;
    if (fs::exists(case_.file, ec)) out.results = io::read_results(case_.file);
    io::CaseRecord record;
    record.key = case_.key;
    record.rank = rank_;
    record.wall_seconds = out.wall_seconds;
    record.scene_digest = scene_digest_;
    io::write_case_record(case_.file, record);
    out.status = Status::ok;
    // Finished: its checkpoint would only make a later sweep continue a done case.
    fs::remove(case_.checkpoint, ec);
    fs::remove(earlier_parts_file(case_), ec);
  } catch (const std::exception& e) {
    out.status = Status::failed;
    out.error = e.what();
  }
}

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

}  // namespace granule::app::sweep_detail
