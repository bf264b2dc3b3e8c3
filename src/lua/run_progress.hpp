// The progress line of a long sim:run: simulated time, percent, steps/s and
// the time left, rewritten in place on stderr. It appears only when a run has
// lasted `delay` seconds (short runs stay silent) and is redrawn at most every
// `interval` seconds, so it costs nothing measurable. The run loop advances the
// engine in chunks and calls update() between them; the engine's step loop
// never sees it.
#pragma once

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>

namespace granule::lua {

class RunProgress {
 public:
  using Clock = std::function<double()>;  // monotonic seconds

  // `total_steps` steps will take the run to simulated time `end_time` [s]; with
  // `open_ended` (a stop_when criterion) that is the most the run will take.
  RunProgress(std::ostream& out, std::int64_t total_steps, double end_time, bool open_ended,
              Clock clock = {}, double delay = 2.0, double interval = 0.25);
  ~RunProgress();  // erases the line if one is shown

  void update(std::int64_t steps_done, double time);
  void finish();  // erases the line (once)
  bool shown() const { return shown_; }

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
  double started_ = 0, last_drawn_ = -1e300;
  bool shown_ = false, finished_ = false;
};

}  // namespace granule::lua
