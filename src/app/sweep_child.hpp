// One case of `granule sweep` as a child process: a plain `granule run` of the
// scene with the case's values, its output and log files, polled until it ends
// (forwarding a stop signal, enforcing --case-timeout) and its outcome read back.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <string>

#include "app/sweep_types.hpp"

namespace granule::app::sweep_detail {

// The signal (SIGINT, SIGTERM, SIGHUP) that asked the sweep to stop; 0 while none.
extern volatile std::sig_atomic_t stop_signal;
void on_stop_signal(int signal);

class RunningCase {
 public:
  // Starts the case (fork and exec of this program); it continues from its
  // checkpoint when an earlier sweep left one.
  RunningCase(const Settings& s, const Case& c, int threads, int rank);
  // Polls; returns true once the case has ended (the outcome is then filled in).
  bool poll(Outcome& out);

 private:
  void finish(Outcome& out);

  Case case_;
  std::string scene_digest_;
  std::uintmax_t log_start_ = 0;  // where this attempt's lines begin in the (appended) log
  int rank_;
  double timeout_;
  std::chrono::steady_clock::time_point start_;
  double earlier_seconds_ =
      0;  // wall time of the case's earlier parts (continued from a checkpoint)
  pid_t pid_ = -1;
  bool forwarded_ = false, timed_out_ = false, continued_ = false;
};

// A worker rank's way: runs one case, waiting on it.
Outcome run_case(const Settings& s, const Case& c, int threads, int rank);

}  // namespace granule::app::sweep_detail
