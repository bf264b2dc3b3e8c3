#include "contact/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/errors.hpp"

namespace granule {

namespace {
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}
}  // namespace

std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(3, name.size() / 3) + 1;
  for (const auto& c : candidates) {
    std::size_t d = edit_distance(name, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

ParamValues resolve_parameters(const std::vector<ParamSpec>& spec, const ParamValues& given,
                               const std::string& context) {
  std::vector<std::string> names;
  for (const auto& p : spec) names.emplace_back(p.name);
  for (const auto& [key, value] : given) {
    if (std::find(names.begin(), names.end(), key) == names.end()) {
      std::string hint = nearest_name(key, names);
      throw InputError(fmt::format("{}: unknown parameter '{}'{}", context, key,
                                   hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
    }
  }
  ParamValues out;
  for (const auto& p : spec) {
    auto it = given.find(p.name);
    double v = it != given.end() ? it->second : p.default_value;
    if (std::isnan(v))
      throw InputError(
          fmt::format("{}: parameter '{}' [{}] is required ({})", context, p.name, p.unit, p.doc));
    if (!std::isfinite(v))
      throw InputError(
          fmt::format("{}: parameter '{}' must be finite, got {}", context, p.name, v));
    bool below = p.min_inclusive ? v < p.min : v <= p.min;
    if (below || v > p.max)
      throw InputError(fmt::format("{}: parameter '{}' = {} [{}] is outside {}{}, {}]", context,
                                   p.name, v, p.unit, p.min_inclusive ? "[" : "(", p.min, p.max));
    out[p.name] = v;
  }
  return out;
}

}  // namespace granule
