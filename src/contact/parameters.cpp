#include "contact/parameters.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/errors.hpp"
#include "core/names.hpp"

namespace granule {

ParamValues resolve_parameters(const std::vector<ParamSpec>& spec, const ParamValues& given,
                               const std::string& context,
                               const std::vector<ParamSpec>& also_hinted) {
  std::vector<std::string> names, hinted;
  for (const auto& p : spec) names.emplace_back(p.name);
  hinted = names;
  for (const auto& p : also_hinted) hinted.emplace_back(p.name);
  for (const auto& [key, value] : given) {
    if (std::find(names.begin(), names.end(), key) == names.end()) {
      std::string hint = nearest_name(key, hinted);
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
      throw InputError(fmt::format("{}: parameter '{}' = {} [{}] is outside {}{}, {}{}", context,
                                   p.name, v, p.unit, p.min_inclusive ? "[" : "(", p.min, p.max,
                                   std::isinf(p.max) ? ")" : "]"));
    if (p.is_switch && v != 0 && v != 1)
      throw InputError(
          fmt::format("{}: parameter '{}' = {} is a switch: give 0 or 1", context, p.name, v));
    out[p.name] = v;
  }
  return out;
}

}  // namespace granule
