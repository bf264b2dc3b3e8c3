#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "contact/parameters.hpp"
#include "core/errors.hpp"
#include "hooks/diagnostic.hpp"

namespace granule {

bool DiagnosticOptions::has(const std::string& key) const {
  return numbers.count(key) || strings.count(key) || lists.count(key);
}

double DiagnosticOptions::number(const std::string& key) {
  use(key);
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
    throw InputError(fmt::format("{}: '{}' must be finite, got {}", context_, key, it->second));
  return it->second;
}

double DiagnosticOptions::number(const std::string& key, double fallback) {
  if (!has(key)) {
    use(key);
    return fallback;
  }
  return number(key);
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
                                        std::int64_t min) {
  double v = number(key, static_cast<double>(fallback));
  if (v != std::floor(v) || v < static_cast<double>(min) || v > 9e15)
    throw InputError(
        fmt::format("{}: '{}' must be an integer >= {}, got {}", context_, key, min, v));
  return static_cast<std::int64_t>(v);
}

bool DiagnosticOptions::boolean(const std::string& key, bool fallback) {
  double v = number(key, fallback ? 1.0 : 0.0);
  if (v != 0 && v != 1)
    throw InputError(fmt::format("{}: '{}' must be true or false", context_, key));
  return v != 0;
}

std::string DiagnosticOptions::string(const std::string& key, const std::string& fallback) {
  use(key);
  auto it = strings.find(key);
  if (it != strings.end()) return it->second;
  if (numbers.count(key) || lists.count(key))
    throw InputError(fmt::format("{}: '{}' must be a string", context_, key));
  return fallback;
}

std::vector<double> DiagnosticOptions::list(const std::string& key,
                                            const std::vector<double>& fallback) {
  use(key);
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
  for (const auto& k : present) {
    if (std::find(used_.begin(), used_.end(), k) != used_.end()) continue;
    std::vector<std::string> known(used_.begin(), used_.end());
    std::string hint = nearest_name(k, known);
    throw InputError(fmt::format("{}: unknown option '{}'{}", context_, k,
                                 hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
  }
}

}  // namespace granule
