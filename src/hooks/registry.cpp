// The diagnostic registry: one line per diagnostic. Adding one means one
// header with a Diagnostic<D> subclass (name, doc, constructor from options),
// one line in Catalogue below, and one test.
#include <fmt/format.h>

#include <tuple>

#include "contact/parameters.hpp"
#include "core/errors.hpp"
#include "hooks/areas.hpp"
#include "hooks/contact_peaks.hpp"
#include "hooks/diagnostic.hpp"
#include "hooks/gap_profile.hpp"
#include "hooks/overlaps.hpp"
#include "hooks/wall_force.hpp"
#include "hooks/zones.hpp"

namespace granule {

namespace {
template <int D>
using Catalogue =
    std::tuple<WallForceDiagnostic<D>, ZonesDiagnostic<D>, AreasDiagnostic<D>,
               ContactPeaksDiagnostic<D>, GapProfileDiagnostic<D>, OverlapsDiagnostic<D>>;

template <int D, std::size_t... I>
std::unique_ptr<Diagnostic<D>> make_by_name(const std::string& name, DiagnosticOptions& options,
                                            std::index_sequence<I...>) {
  std::unique_ptr<Diagnostic<D>> made;
  auto try_one = [&](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    if (!made && name == T::name) made = std::make_unique<T>(options);
  };
  (try_one(static_cast<std::tuple_element_t<I, Catalogue<D>>*>(nullptr)), ...);
  return made;
}
}  // namespace

template <std::size_t... I>
std::vector<DiagnosticInfo> catalogue_of(std::index_sequence<I...>) {
  return {
      {std::tuple_element_t<I, Catalogue<2>>::name, std::tuple_element_t<I, Catalogue<2>>::doc}...};
}

std::vector<DiagnosticInfo> diagnostic_catalogue() {
  return catalogue_of(std::make_index_sequence<std::tuple_size_v<Catalogue<2>>>{});
}

template <int D>
std::unique_ptr<Diagnostic<D>> make_diagnostic(const std::string& name,
                                               DiagnosticOptions& options) {
  auto made =
      make_by_name<D>(name, options, std::make_index_sequence<std::tuple_size_v<Catalogue<D>>>{});
  if (made) return made;
  std::vector<std::string> names;
  for (const auto& d : diagnostic_catalogue()) names.push_back(d.name);
  std::string hint = nearest_name(name, names);
  throw InputError(fmt::format("unknown diagnostic '{}'{} (known: {})", name,
                               hint.empty() ? "" : fmt::format(", did you mean '{}'?", hint),
                               fmt::join(names, ", ")));
}

template std::unique_ptr<Diagnostic<2>> make_diagnostic<2>(const std::string&, DiagnosticOptions&);
template std::unique_ptr<Diagnostic<3>> make_diagnostic<3>(const std::string&, DiagnosticOptions&);

}  // namespace granule
