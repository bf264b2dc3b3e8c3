#include "lua/run_progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <lua.hpp>

namespace granule::lua {

namespace {
double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

RunProgress* active_line = nullptr;  // the terminal line of the run going on (one at a time)

// print and io.write, each behind clear_progress_line(); upvalue 1 is the original.
int cleared_then_original(lua_State* L) {
  clear_progress_line();
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
  return lua_gettop(L);
}

void wrap_function(lua_State* L, int table, const char* name) {
  lua_getfield(L, table, name);
  if (!lua_isfunction(L, -1)) {
    lua_pop(L, 1);
    return;
  }
  lua_pushcclosure(L, cleared_then_original, 1);
  lua_setfield(L, table, name);
}
}  // namespace

void clear_progress_line() {
  if (active_line) active_line->clear();
}

void clear_progress_before_prints(lua_State* L) {
  lua_pushglobaltable(L);
  wrap_function(L, lua_gettop(L), "print");
  lua_pop(L, 1);
  lua_getfield(L, LUA_REGISTRYINDEX, LUA_LOADED_TABLE);
  lua_getfield(L, -1, "io");
  if (lua_istable(L, -1)) wrap_function(L, lua_gettop(L), "write");
  lua_pop(L, 2);
}

RunProgress::RunProgress(std::ostream& out, std::int64_t total_steps, double end_time,
                         bool open_ended, Clock clock, double delay, double interval, Style style,
                         double every_seconds)
    : out_(out),
      total_steps_(total_steps),
      end_time_(end_time),
      open_ended_(open_ended),
      clock_(clock ? std::move(clock) : Clock(steady_seconds)),
      delay_(delay),
      interval_(interval),
      style_(style),
      every_seconds_(every_seconds) {
  started_ = clock_();
  // Every N seconds: the first line N seconds into the run.
  if (style_ == Style::log && every_seconds_ > 0) last_drawn_ = started_;
  if (style_ == Style::terminal) active_line = this;
}

RunProgress::~RunProgress() {
  finish();
}

void RunProgress::update(std::int64_t steps_done, double time) {
  if (finished_ || total_steps_ <= 0 || steps_done <= 0) return;
  const double now = clock_();
  const double elapsed = now - started_;
  if (elapsed < delay_) return;
  const double fraction = std::min(1.0, static_cast<double>(steps_before_ + steps_done) /
                                            static_cast<double>(steps_before_ + total_steps_));
  if (style_ == Style::log) {
    if (every_seconds_ > 0) {
      if (now - last_drawn_ < every_seconds_) return;
    } else {
      // The tenths the run has passed (1e-9: 3 of 10 steps done is 30 %, not 29.99...).
      const int tenth = static_cast<int>(std::floor(fraction * 10 + 1e-9));
      if (tenth <= last_tenth_) return;
      last_tenth_ = tenth;
    }
  } else if (now - last_drawn_ < interval_) {
    return;
  }
  last_drawn_ = now;
  const double rate = steps_done / std::max(elapsed, 1e-9);
  const double left = (total_steps_ - steps_done) / rate;
  const std::string line = format(time, end_time_, fraction, rate, left, open_ended_);
  if (style_ == Style::log) {
    out_ << "progress: " << line << '\n' << std::flush;  // a line of its own, for a log
    return;
  }
  // \r returns to the start of the line, ESC[K clears what a longer line left behind.
  out_ << '\r' << line << "\033[K" << std::flush;
  shown_ = true;
}

void RunProgress::clear() {
  if (!shown_) return;
  out_ << "\r\033[K" << std::flush;
  shown_ = false;
  last_drawn_ = -1e300;  // back at the next update, below what was printed
}

void RunProgress::finish() {
  if (finished_) return;
  finished_ = true;
  if (active_line == this) active_line = nullptr;
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
