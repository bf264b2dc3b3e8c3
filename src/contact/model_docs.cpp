#include "contact/model_docs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "contact/rolling.hpp"
#include "core/errors.hpp"

namespace granule {

namespace {

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

std::string number(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.6g}", v);
}

// A table cell: '|' would end it.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

const char* const begin_prefix = "<!-- BEGIN generated parameters of ";
const char* const begin_suffix = " -->";

}  // namespace

const char* const table_end_marker = "<!-- END generated parameters -->";

std::vector<ContactModelInfo> documented_models() {
  std::vector<ContactModelInfo> out;
  for (const auto& m : contact_model_catalogue())
    if (!m.rolling) out.push_back(m);
  ContactModelInfo rolling;
  rolling.name = "rolling";
  rolling.doc =
      "rolling and twisting resistance, a term any model above carries when its contact gives "
      "rolling_friction > 0 or twisting_friction > 0 (with the model's own parameters): epsd "
      "(default; Ai et al. 2011, type C), a spring k_r = 2.25 k_n mu_r^2 R*^2 on the relative "
      "rolling whose torque is capped at M_m = mu_r R* N (N + 2Nc for thornton_jkr; then it "
      "slips), with a dashpot "
      "2 eta_r sqrt(I_r k_r) while below the cap (I_r = 1 / (1/(I_i + m_i r_i^2) + "
      "1/(I_j + m_j r_j^2))); or constant, M = mu_r R* N against the relative rolling, never "
      "more than stops it within the step; in 3D the same law about the contact normal for the "
      "relative twist, with mu_t, k_t = 2.25 k_n mu_t^2 R*^2 and I_t = 1 / (1/I_i + 1/I_j) "
      "(docs/contact_models.md has the equations)";
  rolling.parameters = rolling_parameters();
  rolling.rolling = true;
  out.push_back(rolling);
  return out;
}

std::string contact_model_names(const std::string& separator) {
  std::vector<std::string> names;
  for (const auto& m : contact_model_catalogue())
    if (!m.rolling) names.push_back(m.name);
  return join(names, separator);
}

std::string batched_model_names(const std::string& separator, int dimension) {
  std::vector<std::string> names;
  for (const auto& m : contact_model_catalogue())
    if (dimension == 3 ? m.batched_3d : m.batched_2d) names.push_back(m.name);
  return join(names, separator);
}

// rolling_model is given by name ("epsd", "constant": rolling.hpp); the table
// holds its code.
bool given_by_name(const ParamSpec& p) {
  return std::string(p.name) == "rolling_model";
}

std::string parameter_range(const ParamSpec& p) {
  if (given_by_name(p)) return "\"epsd\" or \"constant\"";
  if (p.is_switch) return "0 or 1";
  // resolve_parameters: v < min (or <= min) and v > max are refused.
  return fmt::format("{}{}, {}{}", p.min_inclusive ? "[" : "(", number(p.min), number(p.max),
                     std::isinf(p.max) ? ")" : "]");
}

std::string parameter_default(const ParamSpec& p) {
  if (given_by_name(p)) return fmt::format("\"{}\"", rolling_model_name(p.default_value));
  return std::isnan(p.default_value) ? "required" : number(p.default_value);
}

std::string format_model_help(const ContactModelInfo& m) {
  std::string out = fmt::format("{}: {}\n", m.name, m.doc);
  std::size_t name_width = 0, unit_width = 0, range_width = 0;
  for (const auto& p : m.parameters) {
    name_width = std::max(name_width, std::string(p.name).size());
    unit_width = std::max(unit_width, std::string(p.unit).size() + 2);
    range_width = std::max(range_width, parameter_range(p).size());
  }
  for (const auto& p : m.parameters) {
    const std::string def =
        std::isnan(p.default_value) ? "required" : fmt::format("default {}", parameter_default(p));
    out += fmt::format("    {:<{}}  {:<{}}  {:<16} {:<{}}  {}\n", p.name, name_width,
                       fmt::format("[{}]", p.unit), unit_width, def, parameter_range(p),
                       range_width, p.doc);
  }
  return out;
}

std::string format_models_help() {
  std::string out;
  for (const auto& m : documented_models()) out += format_model_help(m);
  return out;
}

std::string models_markdown_list() {
  std::string out;
  for (const auto& m : documented_models()) {
    std::vector<std::string> params;
    for (const auto& p : m.parameters)
      params.push_back(fmt::format("`{}` [{}] {}", p.name, p.unit,
                                   std::isnan(p.default_value)
                                       ? std::string("required")
                                       : fmt::format("= {}", parameter_default(p))));
    out += fmt::format("- `{}`: {}. Parameters: {}.\n", m.name, m.doc, join(params, ", "));
  }
  return out;
}

std::string model_parameter_table(const ContactModelInfo& m) {
  std::string out =
      "| parameter | unit | default | range | meaning |\n"
      "|---|---|---|---|---|\n";
  for (const auto& p : m.parameters)
    out += fmt::format("| `{}` | {} | {} | {} | {} |\n", p.name, p.unit, parameter_default(p),
                       parameter_range(p), cell(p.doc));
  return out;
}

std::string table_begin_marker(const std::string& model) {
  return begin_prefix + model + begin_suffix;
}

std::string regenerate_model_tables(const std::string& page, const std::string& source) {
  const auto catalogue = documented_models();
  const std::string prefix = begin_prefix, suffix = begin_suffix;
  std::istringstream in(page);
  std::string out, line;
  std::set<std::string> seen;
  int number = 0;
  auto starts = [](const std::string& s, const std::string& with) {
    return s.compare(0, with.size(), with) == 0;
  };
  while (std::getline(in, line)) {
    ++number;
    if (starts(line, table_end_marker))
      throw InputError(fmt::format("{}:{}: '{}' without a BEGIN marker before it", source, number,
                                   table_end_marker));
    if (!starts(line, prefix)) {
      out += line + "\n";
      continue;
    }
    const int begin_line = number;
    std::string name = line.substr(prefix.size());
    if (name.size() < suffix.size() ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      throw InputError(
          fmt::format("{}:{}: a table marker reads '{}MODEL{}'", source, number, prefix, suffix));
    name.resize(name.size() - suffix.size());
    auto model = std::find_if(catalogue.begin(), catalogue.end(),
                              [&](const ContactModelInfo& m) { return m.name == name; });
    if (model == catalogue.end())
      throw InputError(
          fmt::format("{}:{}: table marker for unknown contact model '{}' (known: {}, rolling)",
                      source, number, name, contact_model_names(", ")));
    if (!seen.insert(name).second)
      throw InputError(
          fmt::format("{}:{}: a second table for contact model '{}'", source, number, name));
    bool ended = false;
    while (std::getline(in, line)) {
      ++number;
      if (starts(line, table_end_marker)) {
        ended = true;
        break;
      }
    }
    if (!ended)
      throw InputError(fmt::format("{}:{}: the table of '{}' has no '{}' after it", source,
                                   begin_line, name, table_end_marker));
    out +=
        table_begin_marker(name) + "\n" + model_parameter_table(*model) + table_end_marker + "\n";
  }
  for (const auto& m : catalogue)
    if (!seen.count(m.name))
      throw InputError(fmt::format(
          "{}: no parameter table for contact model '{}': add a section for it with the lines "
          "'{}' and '{}'",
          source, m.name, table_begin_marker(m.name), table_end_marker));
  return out;
}

std::string regenerate_model_tables_in(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw InputError(fmt::format("cannot read '{}'", path));
  std::ostringstream text;
  text << file.rdbuf();
  return regenerate_model_tables(text.str(), path);
}

}  // namespace granule
