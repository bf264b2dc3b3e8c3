// granule sweep's summary of all cases: CSV, markdown and HDF5 (docs/performance.md,
// "Parameter sweeps").
#include "app/sweep_summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <ostream>
#include <set>
#include <stdexcept>

#include "io/case_record.hpp"
#include "io/h5_output.hpp"

namespace granule::app::sweep_detail {

namespace {

namespace fs = std::filesystem;
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string number(double v) {
  return fmt::format("{:.10g}", v);
}

// The column each result takes in the summaries: its own name, or
// "result_<name>" where that names a parameter or one of the summaries' own
// columns (prefixed again while that is some other column's), so that none
// is lost (a result `x` beside a swept `x`) and no two share a name.
std::map<std::string, std::string> result_columns(const Settings& s,
                                                  const std::vector<std::string>& results) {
  std::set<std::string> used(std::begin(summary_columns), std::end(summary_columns));
  for (const auto& a : s.axes) used.insert(a.name);
  const std::set<std::string> reserved = used;
  std::map<std::string, std::string> column;
  for (const auto& r : results)
    if (!reserved.count(r)) column[r] = r, used.insert(r);
  for (const auto& r : results) {
    if (!reserved.count(r)) continue;
    std::string c = "result_" + r;
    while (used.count(c)) c = "result_" + c;
    column[r] = c, used.insert(c);
  }
  return column;
}

// Writes `path` through `fill` into path.tmp, renamed into place only once all
// of it reached the disk: a full disk leaves the earlier summary, not an
// empty or cut one.
void write_whole(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot create " + tmp);
    fill(out);
    out.flush();
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + path +
                               " (is the disk full?); the earlier one, if "
                               "any, is kept");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot move " + tmp + " to " + path + ": " + ec.message());
}

}  // namespace

Summary tabulate(const Settings& s, const std::vector<Case>& cases,
                 const std::vector<Outcome>& outcomes, std::vector<std::string>& result_names) {
  std::set<std::string> names;
  for (const auto& o : outcomes)
    for (const auto& r : o.results) names.insert(r.first);
  result_names.assign(names.begin(), names.end());
  Summary t;
  t.header.push_back("case");
  for (const auto& a : s.axes) t.header.push_back(a.name);
  t.header.push_back("status");
  const auto column = result_columns(s, result_names);
  for (const auto& r : result_names) t.header.push_back(column.at(r));
  t.header.insert(t.header.end(), {"rank", "wall_s", "file", "error"});
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Outcome& o = outcomes[i];
    std::vector<std::string> row{std::to_string(i)};
    for (const auto& v : cases[i].values) row.push_back(v.second);
    row.push_back(status_name(o.status));
    for (const auto& r : result_names) {
      auto it = o.results.find(r);
      row.push_back(it == o.results.end() ? "" : number(it->second));
    }
    bool ran = o.status != Status::not_run;
    row.push_back(ran ? std::to_string(o.rank) : "");
    row.push_back(ran ? fmt::format("{:.3f}", o.wall_seconds) : "");
    row.push_back(fs::path(cases[i].file).filename().string());
    row.push_back(o.error);
    t.rows.push_back(std::move(row));
  }
  return t;
}

void write_csv(const std::string& path, const Summary& t) {
  write_whole(path, [&](std::ostream& out) {
    for (std::size_t k = 0; k < t.header.size(); ++k)
      out << (k ? "," : "") << csv_field(t.header[k]);
    out << "\n";
    for (const auto& row : t.rows) {
      for (std::size_t k = 0; k < row.size(); ++k) out << (k ? "," : "") << csv_field(row[k]);
      out << "\n";
    }
  });
}

void markdown(std::ostream& out, const Settings& s, const Summary& t);

void write_markdown(const std::string& path, const Settings& s, const Summary& t) {
  write_whole(path, [&](std::ostream& out) { markdown(out, s, t); });
}

void markdown(std::ostream& out, const Settings& s, const Summary& t) {
  out << "# Sweep of " << s.scene << "\n\n";
  auto cell = [](std::string text) {
    if (text.size() > 100) {
      // Cut at a character's start: a UTF-8 continuation byte is 10xxxxxx.
      std::size_t cut = 97;
      while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
      text = text.substr(0, cut) + "...";
    }
    std::string out;
    for (char c : text)
      out += c == '|'                 ? std::string("\\|")
             : c == '\n' || c == '\r' ? std::string(" ")
                                      : std::string(1, c);
    return out;
  };
  for (const auto& h : t.header) out << "| " << cell(h) << " ";
  out << "|\n";
  for (std::size_t k = 0; k < t.header.size(); ++k) out << "|---";
  out << "|\n";
  for (const auto& row : t.rows) {
    for (const auto& v : row) out << "| " << cell(v) << " ";
    out << "|\n";
  }
}

// One series group /sweep (the form tools/plot_sweep.py reads from one file): a row per
// finished case with every result, numeric parameters and results as columns; the whole
// table (every case, failed ones too) as CSV text in /sweep_table.
void write_h5_file(const std::string& path, const Settings& s, const std::vector<Case>& cases,
                   const std::vector<Outcome>& outcomes,
                   const std::vector<std::string>& result_names, const std::string& csv_text) {
  io::H5Output out(path);
  std::vector<std::size_t> numeric_axes;
  for (std::size_t a = 0; a < s.axes.size(); ++a)
    if (s.axes[a].numeric()) numeric_axes.push_back(a);
  // A row per finished case: the results every one of them reported are its
  // columns; one that some cases lack (a scene reporting it only sometimes)
  // stays in /sweep_table and is named in the attribute partial_results.
  auto finished = [&](const Outcome& o) {
    return o.status == Status::ok || o.status == Status::reused;
  };
  const auto column = result_columns(s, result_names);
  std::vector<std::string> columns{"case"}, partial;
  for (auto a : numeric_axes) columns.push_back(s.axes[a].name);
  for (const auto& r : result_names) {
    const bool everywhere = std::all_of(outcomes.begin(), outcomes.end(), [&](const Outcome& o) {
      auto it = o.results.find(r);
      return !finished(o) || (it != o.results.end() && std::isfinite(it->second));
    });
    if (!everywhere)
      partial.push_back(column.at(r));
    else
      columns.push_back(column.at(r));
  }
  columns.insert(columns.end(), {"rank", "wall_seconds"});
  out.series_declare("/sweep", columns);
  // Each column's unit: a parameter's as its parameters{...} declares it, the wall time's
  // seconds, the case index and rank none; a result's is not known here ('').
  std::vector<std::string> units;
  for (const auto& c : columns) {
    auto declared = s.parameter_units.find(c);
    units.push_back(c == "wall_seconds"                   ? "s"
                    : c == "case" || c == "rank"          ? "-"
                    : declared != s.parameter_units.end() ? declared->second
                                                          : "");
  }
  out.set_series_units("/sweep", units);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Outcome& o = outcomes[i];
    if (!finished(o)) continue;
    std::map<std::string, double> values{
        {"case", double(i)}, {"rank", double(o.rank)}, {"wall_seconds", o.wall_seconds}};
    for (auto a : numeric_axes)
      values[s.axes[a].name] = std::strtod(cases[i].values[a].second.c_str(), nullptr);
    for (const auto& [name, v] : o.results) values[column.at(name)] = v;
    std::vector<double> row;
    for (const auto& c : columns) row.push_back(values.at(c));
    out.series_append("/sweep", row);
  }
  out.write_text("/sweep_table", csv_text);
  out.write_attribute("/sweep", "scene", s.scene);
  out.write_attribute("/sweep", "cases", static_cast<std::int64_t>(cases.size()));
  std::string partial_names;
  for (const auto& r : partial) partial_names += (partial_names.empty() ? "" : ",") + r;
  out.write_attribute("/sweep", "partial_results", partial_names);
  out.flush();
}

void write_h5(const std::string& path, const Settings& s, const std::vector<Case>& cases,
              const std::vector<Outcome>& outcomes, const std::vector<std::string>& result_names,
              const std::string& csv_text) {
  // Written beside and renamed into place, as the CSV.
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  try {
    write_h5_file(tmp, s, cases, outcomes, result_names, csv_text);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot move " + tmp + " to " + path + ": " + ec.message());
}

}  // namespace granule::app::sweep_detail
