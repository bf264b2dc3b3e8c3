// Diagnostics: C++ observers a scene attaches by name (registry.cpp), each
// with its own options. The step calls a diagnostic only on the steps it asks
// for and gathers the contact data only when an attached diagnostic needs it,
// so a scene pays nothing for what it does not attach (the user's third ask).
//
// A diagnostic knows nothing of Lua: it reads options through
// DiagnosticOptions, the step's state through StepView, and writes its rows
// through an OutputSink (the HDF5 run output, when the scene has one).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/particles.hpp"
#include "core/state.hpp"
#include "fields/body_forces.hpp"
#include "geometry/walls.hpp"
#include "hooks/contact_log.hpp"
#include "hooks/sampling.hpp"

namespace granule {

// Where diagnostics write: series (time-stamped rows), attributes, arrays.
class OutputSink {
 public:
  virtual ~OutputSink() = default;
  virtual void declare_series(const std::string& group,
                              const std::vector<std::string>& columns) = 0;
  virtual void append_series(const std::string& group, const std::vector<double>& row) = 0;
  virtual void write_attribute(const std::string& group, const std::string& name, double value) = 0;
  virtual void write_attribute(const std::string& group, const std::string& name,
                               const std::string& value) = 0;
  virtual void write_attribute(const std::string& group, const std::string& name,
                               const std::vector<double>& value) = 0;
};

// One option of a diagnostic: what help() lists and what the option parsing
// checks. A diagnostic's list of them is the one source of truth: a getter
// asked for a key not in it, or with a default other than the listed one, is a
// programming error (std::logic_error), and the scene's keys are checked
// against it (nearest-key hints).
struct OptionDoc {
  std::string key;
  std::string unit;      // SI unit; "-" dimensionless; "" not a physical quantity
  std::string fallback;  // the default as the getter prints it ({a, b} for lists)
  std::string doc;       // one line
  bool required = false;
};
using OptionDocs = std::vector<OptionDoc>;

// Options as the scene gave them: numbers, strings, lists of numbers and
// booleans. Getters throw InputError naming the diagnostic and the key;
// finish() refuses keys the diagnostic does not declare (or, with no
// declaration, keys nobody read), suggesting the nearest known one.
class DiagnosticOptions {
 public:
  explicit DiagnosticOptions(std::string context = "diagnostic") : context_(std::move(context)) {}
  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
  std::map<std::string, std::vector<double>> lists;

  const std::string& context() const { return context_; }
  void set_context(std::string c) { context_ = std::move(c); }
  // The options the diagnostic reads (its descriptors); from then on the
  // getters and finish() check against them.
  void declare(OptionDocs docs) { declared_ = std::move(docs); }
  const OptionDocs& declared() const { return declared_; }
  // The keys the getters were asked for, in order.
  const std::vector<std::string>& read_keys() const { return used_; }
  bool has(const std::string& key) const;
  double number(const std::string& key);  // required
  double number(const std::string& key, double fallback);
  // A number checked against [min, max] (inclusive), naming the unit in the message.
  double number_in(const std::string& key, double fallback, double min, double max,
                   const char* unit);
  // An integer from min to max (checked before any narrowing: 2^32 + 3 is not 3).
  std::int64_t integer(const std::string& key, std::int64_t fallback, std::int64_t min,
                       std::int64_t max = std::int64_t(9e15));
  bool boolean(const std::string& key, bool fallback);  // numbers 0/1 (Lua booleans arrive so)
  std::string string(const std::string& key, const std::string& fallback);
  std::vector<double> list(const std::string& key, const std::vector<double>& fallback);
  void finish() const;

 private:
  std::string context_;
  OptionDocs declared_;
  mutable std::vector<std::string> used_;
  // Notes the key read; with descriptors, checks it is declared with this
  // default (`fallback` as text; nullptr for a getter without one).
  void use(const std::string& key, const std::string* fallback = nullptr) const;
  double finite_number(const std::string& key) const;  // present, a finite number
};

// The state a diagnostic sees: positions x(n), velocities v(n-1/2) and the
// contacts of step n, after the contact forces and before integration.
template <int D>
struct StepView {
  const Particles<D>& particles;
  const std::vector<Wall<D>>& walls;
  const ContactLog<D>& contacts;  // filled only if the diagnostic needs contacts
  double time;                    // s
  double dt;                      // s
  std::int64_t step;
  // Gravity and the central field, which integration adds to the contact forces
  // above (nullptr: none).
  const BodyForces<D>* body = nullptr;
};

// A diagnostic's accumulators in a checkpoint, each under "<prefix><name>":
// doubles as doubles and counts as integers, so a restarted run reports
// exactly what the uninterrupted one reports. The reader refuses a missing or
// wrongly sized entry, naming the key and the diagnostic.
class DiagnosticStateWriter {
 public:
  DiagnosticStateWriter(StateBlob& blob, std::string prefix)
      : blob_(blob), prefix_(std::move(prefix)) {}
  void put(const std::string& key, std::vector<double> values) {
    blob_.doubles[prefix_ + key] = std::move(values);
  }
  void put(const std::string& key, double value) { put(key, std::vector<double>{value}); }
  template <std::size_t N>
  void put(const std::string& key, const std::array<double, N>& values) {
    put(key, std::vector<double>(values.begin(), values.end()));
  }
  void put_integers(const std::string& key, std::vector<std::int64_t> values) {
    blob_.integers[prefix_ + key] = std::move(values);
  }
  void put_integer(const std::string& key, std::int64_t value) { put_integers(key, {value}); }
  template <std::size_t N>
  void put_integers(const std::string& key, const std::array<std::int64_t, N>& values) {
    put_integers(key, std::vector<std::int64_t>(values.begin(), values.end()));
  }
  // The options the diagnostic was attached with, as one line: a restart
  // that attaches it otherwise is refused (DiagnosticStateReader::check_fingerprint).
  void fingerprint(const std::string& line) { blob_.texts[prefix_ + "fingerprint"] = line; }

 private:
  StateBlob& blob_;
  std::string prefix_;
};

class DiagnosticStateReader {
 public:
  static constexpr std::size_t any_size = static_cast<std::size_t>(-1);
  DiagnosticStateReader(const StateBlob& blob, std::string prefix, std::string who)
      : blob_(blob), prefix_(std::move(prefix)), who_(std::move(who)) {}

  std::vector<double> doubles(const std::string& key, std::size_t size) const {
    const auto it = blob_.doubles.find(prefix_ + key);
    if (it == blob_.doubles.end()) throw missing(key);
    check_size(key, it->second.size(), size);
    return it->second;
  }
  double number(const std::string& key) const { return doubles(key, 1)[0]; }
  // Whether an entry is present (for entries that older checkpoints lack).
  bool has(const std::string& key) const {
    return blob_.doubles.count(prefix_ + key) > 0 || blob_.integers.count(prefix_ + key) > 0;
  }
  template <std::size_t N>
  void read(const std::string& key, std::array<double, N>& out) const {
    const auto v = doubles(key, N);
    std::copy(v.begin(), v.end(), out.begin());
  }
  std::vector<std::int64_t> integers(const std::string& key, std::size_t size) const {
    const auto it = blob_.integers.find(prefix_ + key);
    if (it == blob_.integers.end()) throw missing(key);
    check_size(key, it->second.size(), size);
    return it->second;
  }
  std::int64_t integer(const std::string& key) const { return integers(key, 1)[0]; }
  template <std::size_t N>
  void read(const std::string& key, std::array<std::int64_t, N>& out) const {
    const auto v = integers(key, N);
    std::copy(v.begin(), v.end(), out.begin());
  }
  // Refuses a checkpoint whose diagnostic was attached with other options.
  void check_fingerprint(const std::string& now) const {
    const auto it = blob_.texts.find(prefix_ + "fingerprint");
    if (it == blob_.texts.end()) throw missing("fingerprint");
    if (it->second != now)
      throw InputError(fmt::format(
          "checkpoint: diagnostic '{}' was attached with other options (checkpoint: {}; "
          "now: {}); attach it as the checkpointed run did",
          who_, it->second, now));
  }
  const std::string& prefix() const { return prefix_; }
  // A saved value that cannot be the diagnostic's (a negative count, say).
  [[noreturn]] void invalid(const std::string& key, const std::string& why) const {
    throw InputError(
        fmt::format("checkpoint: '{}{}' of diagnostic '{}' {}", prefix_, key, who_, why));
  }

 private:
  InputError missing(const std::string& key) const {
    return InputError(
        fmt::format("checkpoint lacks '{}{}' (the state of diagnostic '{}')", prefix_, key, who_));
  }
  void check_size(const std::string& key, std::size_t got, std::size_t want) const {
    if (want != any_size && got != want)
      throw InputError(fmt::format("checkpoint: '{}{}' has {} values, diagnostic '{}' expects {}",
                                   prefix_, key, got, who_, want));
  }
  const StateBlob& blob_;
  std::string prefix_, who_;
};

// A diagnostic declares its stage (what the step hands it, needs()) and
// reads its trigger and window through the shared Sampling (sampling.hpp);
// the base runs them: the sample stage calls sample() on the trigger's steps
// and close_window() when the window is full, so a diagnostic says only what
// it measures and what a window's row holds. Both stages run after the
// contact forces and before integration (StepView).
template <int D>
class Diagnostic {
 public:
  struct Needs {
    bool contacts = false;  // the contact log on the steps it samples
    bool events = false;    // begin/end events every step (on_events)
  };
  explicit Diagnostic(const char* name) : name_(name) {}
  virtual ~Diagnostic() = default;
  virtual Needs needs() const = 0;

  // For the engine: the steps this divides are candidates for a sample.
  std::int64_t every() const { return sampling_.period(); }
  // The sample stage, on the steps every() divides.
  void observe(const StepView<D>& view) {
    if (!sampling_.due(view.time, view.dt)) return;
    sampling_.note(view.time);
    sample(view);
    if (sampling_.full(view.time, view.dt)) close(view.time, false);
  }
  // Closes a partly filled window (a detach, or when the scene closes the output).
  void flush() {
    if (sampling_.open()) close(sampling_.last(), true);
  }
  const Sampling& sampling() const { return sampling_; }

  // The event stage, every step while needs().events: view.contacts.began /
  // ended hold the step's events.
  virtual void on_events(const StepView<D>&) {}
  // The run output is attached (or replaced): declare series, write settings.
  virtual void attach_output(OutputSink*) {}
  // Scalars a scene can read back (sim:diagnostic_results) and that go to /results.
  virtual std::map<std::string, double> results() const { return {}; }
  // Arrays a scene can read back (profiles, histograms).
  virtual std::map<std::string, std::vector<double>> arrays() const { return {}; }
  // One line for the run header.
  virtual std::string describe() const = 0;
  // Its group under /diagnostics: one diagnostic's, or their rows would mix.
  virtual const std::string& label() const = 0;
  // Its options, trigger and window included, as one line.
  std::string options() const { return fingerprint() + "; " + sampling_.fingerprint(); }

  // Checkpoints: the window's state and every accumulator (anything sample()
  // or on_events() changes) under "<prefix><name>", with a fingerprint of the
  // options; load_state restores them exactly, or throws InputError and
  // leaves the diagnostic as it was. Options are not saved: the restarted
  // scene attaches the diagnostic again.
  void save_state(StateBlob& blob, const std::string& prefix) const {
    DiagnosticStateWriter w(blob, prefix);
    w.fingerprint(fingerprint() + "; " + sampling_.fingerprint());
    sampling_.save(w);
    save_own(w);
  }
  void load_state(const StateBlob& blob, const std::string& prefix) {
    DiagnosticStateReader r(blob, prefix, name_);
    r.check_fingerprint(fingerprint() + "; " + sampling_.fingerprint());
    Sampling s = sampling_;
    s.load(r);
    load_own(r);
    sampling_ = s;
  }

 protected:
  // One sample (the trigger is due); the window is open.
  virtual void sample(const StepView<D>&) {}
  // Writes the full window's row at `time` and empties the window's sums.
  virtual void close_window(double time) = 0;
  // The options other than the trigger and window, as one line.
  virtual std::string fingerprint() const = 0;
  // The accumulators. Pure, so a new diagnostic cannot be checkpointed by
  // silently saving nothing; a stateless one says so with empty bodies.
  // load_own is all or nothing.
  virtual void save_own(DiagnosticStateWriter& w) const = 0;
  virtual void load_own(const DiagnosticStateReader& r) = 0;
  // The trigger and the window as attributes of the diagnostic's group:
  // every_steps (0 under a time trigger), every_time [s] (0 under a step
  // trigger) and window [s].
  void write_sampling_attributes(OutputSink& sink, const std::string& group) const {
    const bool by_time = sampling_.every_seconds() > 0;
    sink.write_attribute(group, "window", sampling_.window());
    sink.write_attribute(group, "every_steps",
                         by_time ? 0.0 : static_cast<double>(sampling_.every_steps()));
    sink.write_attribute(group, "every_time", sampling_.every_seconds());
  }
  Sampling sampling_;

 private:
  void close(double time, bool flushed) {
    close_window(time);
    sampling_.close(time, flushed);
  }
  const char* name_;
};

struct DiagnosticInfo {
  std::string name;
  std::string doc;
  OptionDocs options;
};

// The registry (registry.cpp): one line per diagnostic.
std::vector<DiagnosticInfo> diagnostic_catalogue();
// help("diagnostics") and help("<diagnostic name>"): the diagnostics' options
// from their descriptors, for the terminal or (markdown) docs/lua_api.md; ""
// when the topic is neither.
std::string diagnostics_help(const std::string& topic, bool markdown);
template <int D>
std::unique_ptr<Diagnostic<D>> make_diagnostic(const std::string& name, DiagnosticOptions& options);

}  // namespace granule
