// The diagnostic registry: one line per diagnostic. Adding one means one
// header with a Diagnostic<D> subclass (name, doc, constructor from options),
// one line in Catalogue below, and one test.
#include <fmt/format.h>

#include <algorithm>
#include <tuple>

#include "core/errors.hpp"
#include "core/names.hpp"
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
    if (made || name != T::name) return;
    options.declare(T::options());
    made = std::make_unique<T>(options);
  };
  (try_one(static_cast<std::tuple_element_t<I, Catalogue<D>>*>(nullptr)), ...);
  return made;
}
}  // namespace

template <std::size_t... I>
std::vector<DiagnosticInfo> catalogue_of(std::index_sequence<I...>) {
  return {{std::tuple_element_t<I, Catalogue<2>>::name, std::tuple_element_t<I, Catalogue<2>>::doc,
           std::tuple_element_t<I, Catalogue<2>>::options()}...};
}

std::vector<DiagnosticInfo> diagnostic_catalogue() {
  return catalogue_of(std::make_index_sequence<std::tuple_size_v<Catalogue<2>>>{});
}

namespace {
void option_lines(std::string& out, const DiagnosticInfo& d, bool markdown) {
  if (markdown) {
    out += fmt::format(
        "\n### `{}`\n\n{}.\n\n| option | unit | default | meaning |\n"
        "|---|---|---|---|\n",
        d.name, d.doc);
    for (const auto& o : d.options)
      out += fmt::format("| `{}` | {} | {} | {} |\n", o.key, o.unit,
                         o.required ? "required" : fmt::format("`{}`", o.fallback), o.doc);
    return;
  }
  out += fmt::format("sim:diagnostic('{}', {{ ... }})\n  {}\n", d.name, d.doc);
  std::size_t width = 0;
  for (const auto& o : d.options) width = std::max(width, std::string(o.key).size());
  for (const auto& o : d.options)
    out += fmt::format("    {:<{}}  {:<8} {:<12} {}\n", o.key, width, o.unit,
                       o.required ? "required" : fmt::format("'{}'", o.fallback), o.doc);
}
}  // namespace

std::string diagnostics_help(const std::string& topic, bool markdown) {
  const auto all = diagnostic_catalogue();
  std::string out;
  if (topic == "diagnostics") {
    out = markdown ? "\n## Diagnostics\n\nAttached with `sim:diagnostic(name, { option = value, "
                     "... })`; generated from the diagnostics' descriptors "
                     "(`src/hooks/*.hpp`), which also check the options a scene gives.\n"
                   : "diagnostics (sim:diagnostic(name, { option = value, ... })); help('<name>') "
                     "for one:\n";
    for (const auto& d : all) {
      if (markdown) {
        option_lines(out, d, true);
      } else {
        out += fmt::format("  {:<14} {}\n", d.name, d.doc);
      }
    }
    return out;
  }
  for (const auto& d : all)
    if (d.name == topic) option_lines(out, d, markdown);
  return out;
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
