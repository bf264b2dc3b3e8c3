// Diagnostics: C++ observers a scene attaches by name (registry.cpp), each
// with its own options. The step calls a diagnostic only on the steps it asks
// for and gathers the contact data only when an attached diagnostic needs it,
// so a scene pays nothing for what it does not attach (the user's third ask).
//
// A diagnostic knows nothing of Lua: it reads options through
// DiagnosticOptions, the step's state through StepView, and writes its rows
// through an OutputSink (the HDF5 run output, when the scene has one).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "geometry/walls.hpp"
#include "hooks/contact_log.hpp"

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

// Options as the scene gave them: numbers, strings, lists of numbers and
// booleans. Getters throw InputError naming the diagnostic and the key;
// finish() refuses keys nobody read, suggesting the nearest known one.
class DiagnosticOptions {
 public:
  explicit DiagnosticOptions(std::string context = "diagnostic") : context_(std::move(context)) {}
  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;
  std::map<std::string, std::vector<double>> lists;

  const std::string& context() const { return context_; }
  void set_context(std::string c) { context_ = std::move(c); }
  bool has(const std::string& key) const;
  double number(const std::string& key);  // required
  double number(const std::string& key, double fallback);
  // A number checked against [min, max] (inclusive), naming the unit in the message.
  double number_in(const std::string& key, double fallback, double min, double max,
                   const char* unit);
  std::int64_t integer(const std::string& key, std::int64_t fallback, std::int64_t min);
  bool boolean(const std::string& key, bool fallback);  // numbers 0/1 (Lua booleans arrive so)
  std::string string(const std::string& key, const std::string& fallback);
  std::vector<double> list(const std::string& key, const std::vector<double>& fallback);
  void finish() const;

 private:
  std::string context_;
  mutable std::vector<std::string> used_;
  void use(const std::string& key) const { used_.push_back(key); }
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
};

template <int D>
class Diagnostic {
 public:
  struct Needs {
    bool contacts = false;  // the contact log on the steps observe() is called
    bool events = false;    // begin/end events every step (on_events)
  };
  virtual ~Diagnostic() = default;
  virtual Needs needs() const = 0;
  // Steps between observe() calls (1 = every step).
  virtual std::int64_t every() const = 0;
  virtual void observe(const StepView<D>& view) = 0;
  // Every step while needs().events: view.contacts.began / ended hold the step's events.
  virtual void on_events(const StepView<D>&) {}
  // The run output is attached (or replaced): declare series, write settings.
  virtual void attach_output(OutputSink*) {}
  // Flushes a partly filled window (end of a run, or when the scene closes the output).
  virtual void flush() {}
  // Scalars a scene can read back (sim:diagnostic_results) and that go to /results.
  virtual std::map<std::string, double> results() const { return {}; }
  // Arrays a scene can read back (profiles, histograms).
  virtual std::map<std::string, std::vector<double>> arrays() const { return {}; }
  // One line for the run header.
  virtual std::string describe() const = 0;
};

struct DiagnosticInfo {
  std::string name;
  std::string doc;
};

// The registry (registry.cpp): one line per diagnostic.
std::vector<DiagnosticInfo> diagnostic_catalogue();
template <int D>
std::unique_ptr<Diagnostic<D>> make_diagnostic(const std::string& name, DiagnosticOptions& options);

}  // namespace granule
