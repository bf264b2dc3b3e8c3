// The progress line of a long sim:run: simulated time, percent, steps/s and
// the time left. On a terminal it is rewritten in place on stderr, at most every
// `interval` seconds, and erased before the scene prints (print and io.write go
// through clear_progress_line()), so it never shares a line with them. For a
// batch log (stderr not a terminal) it is a line of its own, "progress: ...",
// at every tenth of the run, or every `every_seconds` of wall time when that is
// > 0. Either appears only when a run has lasted `delay` seconds (short runs stay
// silent), so it costs nothing measurable. The run loop advances the engine in
// chunks and calls update() between them; the engine's step loop never sees it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

struct lua_State;

namespace granule::lua {

class RunProgress {
 public:
  using Clock = std::function<double()>;  // monotonic seconds
  enum class Style { terminal, log };

  // `total_steps` steps will take the run to simulated time `end_time` [s]; with
  // `open_ended` (a stop_when criterion) that is the most the run will take.
  RunProgress(std::ostream& out, std::int64_t total_steps, double end_time, bool open_ended,
              Clock clock = {}, double delay = 2.0, double interval = 0.25,
              Style style = Style::terminal, double every_seconds = 0);
  ~RunProgress();  // erases the line if one is shown
  RunProgress(const RunProgress&) = delete;
  RunProgress& operator=(const RunProgress&) = delete;

  void update(std::int64_t steps_done, double time);
  // The run's length counted again (a shorter time step on the way).
  void retarget(std::int64_t total_steps) { total_steps_ = total_steps; }
  // A run continued from a checkpoint: `steps` of it were taken before, so the
  // percentage is of the whole run, as the times beside it are (the rate and the
  // time left count this process's steps).
  void continued_after(std::int64_t steps) {
    steps_before_ = std::max<std::int64_t>(0, steps);
    last_tenth_ = static_cast<int>(10 * static_cast<double>(steps_before_) /
                                   static_cast<double>(steps_before_ + total_steps_));
  }
  void finish();  // erases the line (once)
  bool shown() const { return shown_; }
  // Erases the terminal line now (it is redrawn at the next update), so that what
  // the scene prints starts on a line of its own.
  void clear();

  // "t = 0.0123 s of 0.05 s  24.6%  1.83e+04 steps/s  ETA 0:42"
  static std::string format(double time, double end_time, double fraction, double steps_per_second,
                            double seconds_left, bool open_ended);
  // "0:42", "12:05", "3:02:09"
  static std::string format_duration(double seconds);

 private:
  std::ostream& out_;
  std::int64_t total_steps_;
  double end_time_;
  bool open_ended_;
  Clock clock_;
  double delay_, interval_;
  Style style_;
  double every_seconds_;
  double started_ = 0, last_drawn_ = -1e300;
  int last_tenth_ = 0;             // log style: the last tenth of the run reported
  std::int64_t steps_before_ = 0;  // of a continued run, taken before it was continued
  bool shown_ = false, finished_ = false;
};

// Erases the terminal progress line of the run going on, if one is shown.
void clear_progress_line();
// Makes the state's print and io.write call clear_progress_line() first.
void clear_progress_before_prints(lua_State* L);

}  // namespace granule::lua
