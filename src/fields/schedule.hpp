// A value that follows simulated time: the ramps of a protocol (field
// strength, friction, surface energy, wall speed) stated once instead of as a
// script loop, and evaluated in C++ before every step.
//
// Every form is a list of points (t_k, v_k) with t_k non-decreasing, the
// value linear between neighbours and held before the first and after the
// last point:
//   constant v               one point (0, v)
//   linear t0, v0, t1, v1    two points: v0 until t0, then linear to v1 at t1, then v1
//   piecewise {t, v, ...}    the points in order
// Two points at the same time are a jump: from that time on, the later
// value holds.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/errors.hpp"

namespace granule {

class Schedule {
 public:
  Schedule() = default;
  static Schedule constant(double v, const std::string& what) {
    return Schedule("constant", {0.0}, {v}, what);
  }
  static Schedule linear(double t0, double v0, double t1, double v1, const std::string& what) {
    if (std::isfinite(t0) && std::isfinite(t1) && !(t1 > t0))
      throw InputError(
          fmt::format("{}: linear needs t1 > t0, got t0 = {} s and t1 = {} s", what, t0, t1));
    return Schedule("linear", {t0, t1}, {v0, v1}, what);
  }
  static Schedule piecewise(std::vector<double> times, std::vector<double> values,
                            const std::string& what) {
    return Schedule("piecewise", std::move(times), std::move(values), what);
  }

  // The value at time t [s].
  double at(double t) const {
    if (t < times_.front()) return values_.front();
    if (t >= times_.back()) return values_.back();
    // The last point at or before t: after a jump (equal times), the later value.
    const std::size_t k = static_cast<std::size_t>(
                              std::upper_bound(times_.begin(), times_.end(), t) - times_.begin()) -
                          1;
    const double t0 = times_[k], t1 = times_[k + 1];
    return values_[k] + (values_[k + 1] - values_[k]) * ((t - t0) / (t1 - t0));
  }
  const std::string& form() const { return form_; }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& values() const { return values_; }
  bool empty() const { return times_.empty(); }
  // One line: "linear (0, 1) .. (0.1, 2)".
  std::string describe() const {
    std::string out = form_;
    for (std::size_t k = 0; k < times_.size(); ++k)
      out += fmt::format("{}({:g} s, {:g})", k == 0 ? " " : " .. ", times_[k], values_[k]);
    return out;
  }

 private:
  Schedule(std::string form, std::vector<double> times, std::vector<double> values,
           const std::string& what)
      : form_(std::move(form)), times_(std::move(times)), values_(std::move(values)) {
    if (times_.empty())
      throw InputError(fmt::format("{}: a {} schedule needs at least one point", what, form_));
    if (times_.size() != values_.size())
      throw InputError(fmt::format("{}: {} times but {} values (one value per time)", what,
                                   times_.size(), values_.size()));
    for (std::size_t k = 0; k < times_.size(); ++k) {
      if (!std::isfinite(times_[k]))
        throw InputError(
            fmt::format("{}: time {} is {} (times must be finite, in s)", what, k + 1, times_[k]));
      if (!std::isfinite(values_[k]))
        throw InputError(fmt::format("{}: value {} (at t = {} s) is {} (values must be finite)",
                                     what, k + 1, times_[k], values_[k]));
      if (k > 0 && times_[k] < times_[k - 1])
        throw InputError(fmt::format(
            "{}: time goes backwards at point {} ({} s after {} s); give the points in time order",
            what, k + 1, times_[k], times_[k - 1]));
    }
  }
  std::string form_;
  std::vector<double> times_, values_;
};

// What a schedule drives (SimulationBase::add_schedule, simulation_schedules.cpp):
//   central_strength                the central field's strength [m/s^2] (7.3)
//   wall_angular_velocity  wall     a cylinder's angular velocity [rad/s]
//   wall_velocity          wall     a plane's velocity [m/s]: the value times `direction`
//   <contact parameter>    a, b     friction, surface_energy or any other parameter of
//                                   the a-b pair's model (its units)
struct ScheduleSpec {
  std::string target;
  std::string a, b;                          // materials, or a = the wall
  std::array<double, 3> direction{1, 0, 0};  // wall_velocity: a unit vector
  Schedule schedule;
  int wall = -1;  // resolved
  int id = 0;     // sim:schedule's answer, for sim:remove_schedule
  // The value last set; a schedule sets its target only when the value changes.
  double applied = std::nan("");
};

}  // namespace granule
