// granule sweep's command line and its cases: every combination of the -D value
// lists, each with its file names (docs/performance.md, "Parameter sweeps").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "app/sweep_types.hpp"

namespace granule::app::sweep_detail {

namespace fs = std::filesystem;

namespace {
// ---- the command line ----

// "a,b\,c" -> {"a", "b,c"}: a backslash keeps a comma inside a value.
std::vector<std::string> split_values(const std::string& text) {
  std::vector<std::string> out(1);
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '\\' && k + 1 < text.size() && text[k + 1] == ',') {
      out.back() += ',';
      ++k;
    } else if (text[k] == ',') {
      out.emplace_back();
    } else {
      out.back() += text[k];
    }
  }
  return out;
}

void add_axis(Settings& s, const std::string& arg) {
  auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0)
    throw UsageError("-D expects name=value or name=v1,v2,..., got '" + arg + "'");
  Axis axis{arg.substr(0, eq), split_values(arg.substr(eq + 1))};
  for (const auto& other : s.axes)
    if (other.name == axis.name) throw UsageError("-D " + axis.name + " given twice");
  for (const char* own : summary_columns)
    if (axis.name == own)
      throw UsageError(fmt::format(
          "-D {}: '{}' names a column of the sweep's summary (case, status, rank, wall_s, "
          "wall_seconds, file, error); rename the scene's parameter",
          arg, axis.name));
  std::set<std::string> seen;
  for (std::size_t k = 0; k < axis.values.size(); ++k) {
    const std::string& v = axis.values[k];
    if (v.empty())
      throw UsageError(fmt::format("-D {}: value {} of '{}' is empty", arg, k + 1, axis.name));
    if (!seen.insert(v).second)
      throw UsageError(fmt::format("-D {}: '{}' lists {} twice", arg, axis.name, v));
  }
  // "1" and "1.0" are one case, run twice, on an axis of numbers (a text
  // parameter's "1" and "01" differ); an integer of more than 15 digits is past
  // what a double tells apart.
  if (axis.numeric()) {
    std::map<double, std::string> numbers;
    for (const auto& v : axis.values) {
      if (std::count_if(v.begin(), v.end(), [](char c) { return c >= '0' && c <= '9'; }) > 15)
        continue;
      auto [at, fresh] = numbers.emplace(std::strtod(v.c_str(), nullptr), v);
      if (!fresh)
        throw UsageError(fmt::format("-D {}: '{}' lists {} and {}, the same number, twice", arg,
                                     axis.name, at->second, v));
    }
  }
  s.axes.push_back(std::move(axis));
}

}  // namespace

Settings parse(const std::vector<std::string>& args) {
  Settings s;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    auto value = [&]() -> const std::string& {
      if (k + 1 >= args.size()) throw UsageError(a + " needs a value");
      return args[++k];
    };
    if (a == "-D") {
      add_axis(s, value());
    } else if (a.rfind("-D", 0) == 0 && a.size() > 2) {
      add_axis(s, a.substr(2));
    } else if (a == "-o") {
      const std::string& v = value();
      if (v.empty()) throw UsageError("-o needs a directory name");
      if (!s.directory.empty()) throw UsageError("-o given twice");
      s.directory = v;
    } else if (a == "--threads") {
      const std::string& v = value();
      char* end = nullptr;
      long n = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != 0 || n < 1 || n > 4096)
        throw UsageError("--threads expects a whole number from 1 to 4096, got '" + v + "'");
      s.threads = static_cast<int>(n);
    } else if (a == "-q" || a == "--quiet") {
      s.quiet = true;
    } else if (a == "--list") {
      s.list_only = true;
    } else if (a == "--case-timeout") {
      const std::string& v = value();
      char* end = nullptr;
      double t = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != 0 || !(t > 0) || !std::isfinite(t))
        throw UsageError("--case-timeout expects seconds > 0, got '" + v + "'");
      s.case_timeout = t;
    } else if (a == "--checkpoint-every") {
      const std::string& v = value();
      char* end = nullptr;
      double t = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != 0 || !(t >= 0) || !std::isfinite(t))
        throw UsageError("--checkpoint-every expects seconds >= 0 (0: none), got '" + v + "'");
      s.checkpoint_every = t;
    } else if (a == "--restart") {
      throw UsageError(
          "--restart is for one run; a sweep continues each unfinished case from its own "
          "checkpoint");
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError("unknown option '" + a + "'");
    } else if (s.scene.empty()) {
      s.scene = a;
    } else {
      throw UsageError("more than one scene file given ('" + s.scene + "', '" + a + "')");
    }
  }
  if (s.scene.empty()) throw UsageError("sweep needs a scene file");
  std::error_code ec;
  if (!fs::is_regular_file(s.scene, ec))
    throw UsageError(fs::exists(s.scene, ec) ? "'" + s.scene + "' is not a scene file"
                                             : "cannot open scene file '" + s.scene + "'");
  if (s.directory.empty()) s.directory = fs::path(s.scene).stem().string() + "_sweep";
  return s;
}

// ---- the cases ----

namespace {
std::string file_safe(const std::string& text) {
  std::string out;
  for (char c : text)
    out += (std::isalnum(static_cast<unsigned char>(c)) || std::strchr("._+-", c)) ? c : '_';
  return out;
}

}  // namespace

std::vector<Case> make_cases(const Settings& s) {
  std::size_t total = 1;
  for (const auto& a : s.axes) total *= a.values.size();
  const std::string stem = fs::path(s.scene).stem().string();
  std::vector<Case> cases(total);
  std::map<std::string, int> names_used;
  for (std::size_t i = 0; i < total; ++i) {
    Case& c = cases[i];
    c.index = i;
    // The last -D varies fastest, like nested loops written in the order given.
    std::size_t rest = i;
    std::vector<std::size_t> pick(s.axes.size());
    for (std::size_t a = s.axes.size(); a-- > 0;) {
      pick[a] = rest % s.axes[a].values.size();
      rest /= s.axes[a].values.size();
    }
    // The file is named by the values that vary; the key (kept in the file when the case
    // has finished) holds them all, so a case rerun with another fixed value is run again.
    std::string name = stem;
    for (std::size_t a = 0; a < s.axes.size(); ++a) {
      const std::string& v = s.axes[a].values[pick[a]];
      c.values.emplace_back(s.axes[a].name, v);
      c.key += (a ? ";" : "") + s.axes[a].name + "=" + v;
      if (s.axes[a].values.size() > 1) name += "_" + file_safe(s.axes[a].name) + "=" + file_safe(v);
    }
    c.file = name;
    ++names_used[name];
  }
  for (Case& c : cases) {
    // Values that differ only in characters a file name cannot hold, or names too long
    // for a file system, fall back to the case number (the key inside tells them apart).
    if (names_used[c.file] > 1 || c.file.size() > 200)
      c.file = fmt::format("{}_case{:04d}", stem, c.index);
    fs::path base = fs::path(s.directory) / c.file;
    c.file = base.string() + ".h5";
    c.log = base.string() + ".log";
    c.checkpoint = base.string() + ".checkpoint.h5";
  }
  return cases;
}

}  // namespace granule::app::sweep_detail
