// When a diagnostic samples and over what it averages, one component for
// every diagnostic (the Diagnostic<D> base owns it; diagnostic.hpp):
//
// The trigger: every N steps (step counts divisible by N, as the engine
// counts them), or every T seconds of simulated time: on the step nearest
// each multiple of T, i.e. when [t - dt/2, t + dt/2) holds one (every step
// if T < dt). Both are functions of the step alone, so a restarted run
// samples on the same steps without saving anything.
//
// The window: it opens at the first sample after the last close and closes
// at the first sample whose time reaches its start plus the window length
// (within half a step, so that a window of k dt closes on the k-th step
// rather than on the (k+1)-th when the sum of the steps rounds down); the
// next window starts where the last one was due to end, not at the sample
// that closed it, so that windows keep their length on average when the
// sample period does not divide it (every 3 steps into a window of 10: 12,
// 9, 9, 12, ... steps, not 12 each) and their times stay near multiples of
// it. A sample period longer than the window closes a window at every
// sample. A window runs on across the scene's runs; a detach or the output's
// closing closes one holding samples (flush), the next then starting at its
// last sample.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "core/errors.hpp"
#include "core/state.hpp"

namespace granule {

class DiagnosticOptions;
class DiagnosticStateWriter;
class DiagnosticStateReader;
struct OptionDoc;

class Sampling {
 public:
  // The defaults a diagnostic gives its options. every = 0: the diagnostic
  // takes no trigger options and is called every step (it works on events).
  struct Defaults {
    std::int64_t every = 10;  // steps
    double window = 0.01;     // s
    const char* window_doc = "averaging window of the series";
  };
  static void add_option_docs(std::vector<OptionDoc>& docs, const Defaults& d);
  void read(DiagnosticOptions& o, const Defaults& d);

  // Steps between the engine's calls: every N, or 1 for a time trigger.
  std::int64_t period() const { return every_seconds_ > 0 ? 1 : every_steps_; }
  // On a step the period divides: is this a sample?
  bool due(double time, double dt) const {
    if (!(every_seconds_ > 0)) return true;
    return std::floor((time + 0.5 * dt) / every_seconds_) !=
           std::floor((time - 0.5 * dt) / every_seconds_);
  }
  // A sample at `time`: opens the window if none is open.
  void note(double time) {
    if (start_ < 0) start_ = time;
    last_ = time;
    ++samples_;
  }
  bool full(double time, double dt) const { return time + 0.5 * dt >= start_ + window_; }
  // The window closed at `time`, full or (`flushed`) cut short.
  void close(double time, bool flushed) {
    const double due = start_ + window_;
    start_ = flushed || !(time - due < window_) ? time : due;
    samples_ = 0;
  }
  bool open() const { return samples_ > 0; }
  double last() const { return last_; }
  double window() const { return window_; }
  std::int64_t every_steps() const { return every_steps_; }
  double every_seconds() const { return every_seconds_; }

  // The options, as a restart must give them again.
  std::string fingerprint() const {
    return fmt::format("every {}; every_time {:.17g}; window {:.17g}", every_steps_, every_seconds_,
                       window_);
  }
  // The description's part: "every 10 steps, 0.01 s windows".
  std::string describe() const {
    return every_seconds_ > 0 ? fmt::format("every {} s, {} s windows", every_seconds_, window_)
                              : fmt::format("every {} steps, {} s windows", every_steps_, window_);
  }
  void save(DiagnosticStateWriter& w) const;
  void load(const DiagnosticStateReader& r);

 private:
  std::int64_t every_steps_ = 1;
  double every_seconds_ = 0;
  double window_ = 0.01;
  double start_ = -1, last_ = 0;  // s; start < 0: no sample yet
  std::int64_t samples_ = 0;      // in the open window
};

}  // namespace granule
