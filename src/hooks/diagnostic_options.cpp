#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/errors.hpp"
#include "core/names.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

namespace {
std::string as_text(double v) {
  return fmt::format("{}", v);
}
std::string as_text(const std::vector<double>& v) {
  return fmt::format("{{{}}}", fmt::join(v, ", "));
}
}  // namespace

void DiagnosticOptions::use(const std::string& key, const std::string* fallback) const {
  used_.push_back(key);
  if (declared_.empty()) return;
  const auto it = std::find_if(declared_.begin(), declared_.end(),
                               [&](const OptionDoc& d) { return key == d.key; });
  if (it == declared_.end())
    throw std::logic_error(
        fmt::format("{}: reads option '{}', which it does not declare", context_, key));
  if (fallback && !it->required && *fallback != it->fallback)
    throw std::logic_error(
        fmt::format("{}: option '{}' defaults to {} in the code but to {} in its descriptor",
                    context_, key, *fallback, it->fallback));
}

bool DiagnosticOptions::has(const std::string& key) const {
  return numbers.count(key) || strings.count(key) || lists.count(key);
}

double DiagnosticOptions::number(const std::string& key) {
  use(key);
  return finite_number(key);
}

double DiagnosticOptions::finite_number(const std::string& key) const {
  auto it = numbers.find(key);
  if (it == numbers.end()) {
    // number(key, fallback) comes here for a key that is present, so a given
    // key of the wrong kind must be told apart from a missing one.
    if (auto text = strings.find(key); text != strings.end())
      throw InputError(
          fmt::format("{}: '{}' must be a number, got the text '{}'", context_, key, text->second));
    if (lists.count(key))
      throw InputError(fmt::format("{}: '{}' must be a number, got a list", context_, key));
    throw InputError(fmt::format("{}: '{}' is required (a number)", context_, key));
  }
  if (!std::isfinite(it->second))
    throw InputError(
        fmt::format("{}: '{}' must be finite, got {}", context_, key, number_text(it->second)));
  return it->second;
}

double DiagnosticOptions::number(const std::string& key, double fallback) {
  const std::string text = as_text(fallback);
  use(key, &text);
  return has(key) ? finite_number(key) : fallback;
}

double DiagnosticOptions::number_in(const std::string& key, double fallback, double min, double max,
                                    const char* unit) {
  double v = number(key, fallback);
  if (!(v >= min && v <= max))
    throw InputError(
        fmt::format("{}: '{}' must be in [{}, {}] [{}], got {}", context_, key, min, max, unit, v));
  return v;
}

std::int64_t DiagnosticOptions::integer(const std::string& key, std::int64_t fallback,
                                        std::int64_t min, std::int64_t max) {
  double v = number(key, static_cast<double>(fallback));
  if (v != std::floor(v) || v < static_cast<double>(min) || v > static_cast<double>(max))
    throw InputError(
        max < std::int64_t(9e15)
            ? fmt::format("{}: '{}' must be an integer from {} to {}, got {}", context_, key, min,
                          max, v)
            : fmt::format("{}: '{}' must be an integer >= {}, got {}", context_, key, min, v));
  return static_cast<std::int64_t>(v);
}

bool DiagnosticOptions::boolean(const std::string& key, bool fallback) {
  const std::string text = fallback ? "true" : "false";
  use(key, &text);
  const double v = has(key) ? finite_number(key) : (fallback ? 1.0 : 0.0);
  if (v != 0 && v != 1)
    throw InputError(fmt::format("{}: '{}' must be true or false", context_, key));
  return v != 0;
}

std::string DiagnosticOptions::string(const std::string& key, const std::string& fallback) {
  use(key, &fallback);
  auto it = strings.find(key);
  if (it != strings.end()) return it->second;
  if (numbers.count(key) || lists.count(key))
    throw InputError(fmt::format("{}: '{}' must be a string", context_, key));
  return fallback;
}

std::vector<double> DiagnosticOptions::list(const std::string& key,
                                            const std::vector<double>& fallback) {
  const std::string text = as_text(fallback);
  use(key, &text);
  auto it = lists.find(key);
  if (it == lists.end()) {
    if (numbers.count(key) || strings.count(key))
      throw InputError(fmt::format("{}: '{}' must be a list of numbers", context_, key));
    return fallback;
  }
  for (double v : it->second)
    if (!std::isfinite(v))
      throw InputError(fmt::format("{}: '{}' must hold finite numbers", context_, key));
  return it->second;
}

void DiagnosticOptions::finish() const {
  std::vector<std::string> present;
  for (const auto& [k, v] : numbers) present.push_back(k);
  for (const auto& [k, v] : strings) present.push_back(k);
  for (const auto& [k, v] : lists) present.push_back(k);
  std::vector<std::string> known;
  if (declared_.empty()) {
    known.assign(used_.begin(), used_.end());
  } else {
    for (const auto& d : declared_) known.push_back(d.key);
  }
  for (const auto& k : present) {
    if (std::find(known.begin(), known.end(), k) != known.end()) continue;
    std::string hint = nearest_name(k, known);
    throw InputError(fmt::format("{}: unknown option '{}'{}", context_, k,
                                 hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
  }
}

// ---- Sampling (sampling.hpp): the shared trigger and window ----

void Sampling::add_option_docs(std::vector<OptionDoc>& docs, const Defaults& d) {
  if (d.every > 0) {
    docs.push_back({"every", "steps", fmt::format("{}", static_cast<double>(d.every)),
                    "steps between samples"});
    docs.push_back({"every_time", "s", "0",
                    "> 0: sample on the step nearest each multiple of this instead of every N "
                    "steps"});
  }
  docs.push_back({"window", "s", fmt::format("{}", d.window), d.window_doc});
}

void Sampling::read(DiagnosticOptions& o, const Defaults& d) {
  if (d.every > 0) {
    every_steps_ = o.integer("every", d.every, 1);
    every_seconds_ = o.number_in("every_time", 0, 0, 1e9, "s");
    if (every_seconds_ > 0 && o.has("every"))
      throw InputError(
          fmt::format("{}: give 'every' (steps) or 'every_time' (s), not both", o.context()));
    if (every_seconds_ > 0) every_steps_ = 1;
  }
  window_ = o.number_in("window", d.window, 0, 1e9, "s");
  if (!(window_ > 0)) throw InputError(fmt::format("{}: window must be > 0 [s]", o.context()));
}

void Sampling::save(DiagnosticStateWriter& w) const {
  w.put("sampling.window", {start_, last_});
  w.put_integer("sampling.samples", samples_);
}

void Sampling::load(const DiagnosticStateReader& r) {
  const auto times = r.doubles("sampling.window", 2);
  const auto samples = r.integer("sampling.samples");
  if (samples < 0) r.invalid("sampling.samples", "is negative");
  start_ = times[0], last_ = times[1], samples_ = samples;
}

}  // namespace granule
