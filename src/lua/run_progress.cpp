#include "lua/run_progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace granule::lua {

namespace {
double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

RunProgress::RunProgress(std::ostream& out, std::int64_t total_steps, double end_time,
                         bool open_ended, Clock clock, double delay, double interval)
    : out_(out),
      total_steps_(total_steps),
      end_time_(end_time),
      open_ended_(open_ended),
      clock_(clock ? std::move(clock) : Clock(steady_seconds)),
      delay_(delay),
      interval_(interval) {
  started_ = clock_();
}

RunProgress::~RunProgress() {
  finish();
}

void RunProgress::update(std::int64_t steps_done, double time) {
  if (finished_ || total_steps_ <= 0 || steps_done <= 0) return;
  const double now = clock_();
  const double elapsed = now - started_;
  if (elapsed < delay_ || now - last_drawn_ < interval_) return;
  last_drawn_ = now;
  const double rate = steps_done / std::max(elapsed, 1e-9);
  const double fraction = std::min(1.0, static_cast<double>(steps_done) / total_steps_);
  const double left = (total_steps_ - steps_done) / rate;
  // \r returns to the start of the line, ESC[K clears what a longer line left behind.
  out_ << '\r' << format(time, end_time_, fraction, rate, left, open_ended_) << "\033[K"
       << std::flush;
  shown_ = true;
}

void RunProgress::finish() {
  if (finished_) return;
  finished_ = true;
  if (shown_) out_ << "\r\033[K" << std::flush;
}

std::string RunProgress::format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  auto total = static_cast<long long>(std::llround(std::min(seconds, 1e9)));
  long long h = total / 3600, m = total / 60 % 60, s = total % 60;
  if (h > 0) return fmt::format("{}:{:02d}:{:02d}", h, m, s);
  return fmt::format("{}:{:02d}", m, s);
}

std::string RunProgress::format(double time, double end_time, double fraction,
                                double steps_per_second, double seconds_left, bool open_ended) {
  return fmt::format("t = {:.4g} s of {:.4g} s  {:5.1f}%  {:.3g} steps/s  ETA {}{}", time, end_time,
                     100 * fraction, steps_per_second, format_duration(seconds_left),
                     open_ended ? " (at most)" : "");
}

}  // namespace granule::lua
