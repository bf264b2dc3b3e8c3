// The types granule sweep's parts share: the command line's settings, one case
// (its values and files) and what became of it.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace granule::app::sweep_detail {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Axis {
  std::string name;
  std::vector<std::string> values;
  // Every value a finite number: the summary gives the axis a column of numbers.
  bool numeric() const {
    for (const auto& v : values) {
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != 0 || !std::isfinite(x)) return false;
    }
    return true;
  }
};

// The summaries' own columns (CSV, markdown, HDF5 /sweep): no parameter may
// take these names, and a result named so takes result_<name>.
inline constexpr const char* summary_columns[] = {"case",         "status", "rank", "wall_s",
                                                  "wall_seconds", "file",   "error"};

struct Settings {
  std::string scene, directory;
  std::string scene_digest;  // io::source_digest of the scene's text, read once
  std::vector<Axis> axes;
  int threads = 0;  // 0: the scene's own choice (or, under MPI, the cores shared out)
  bool quiet = false;
  bool list_only = false;   // --list: print the cases and their files, run nothing
  double case_timeout = 0;  // s of wall time per case; 0 = none
  // Each case writes a checkpoint this often (s of wall time; 0: none but the one a
  // signal writes), and a case that did not finish continues from it on the next sweep.
  double checkpoint_every = 600;
  // Each declared parameter's unit (from its parameters{...}), for the summary's columns.
  std::map<std::string, std::string> parameter_units;
};

struct Case {
  std::size_t index = 0;
  std::vector<std::pair<std::string, std::string>> values;  // in -D order
  std::string key;                                          // "name=value;..."
  std::string file, log;
  std::string checkpoint;  // where the case's run writes its checkpoints
};

enum class Status { ok, reused, failed, interrupted, not_run };

inline const char* status_name(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::reused:
      return "reused";
    case Status::failed:
      return "failed";
    case Status::interrupted:
      return "interrupted";
    case Status::not_run:
      return "not run";
  }
  return "?";
}

struct Outcome {
  std::size_t index = 0;
  Status status = Status::not_run;
  std::string error;
  int rank = 0;
  double wall_seconds = 0;
  std::map<std::string, double> results;
  int stop_signal = 0;     // the signal an interrupted case stopped on, when its status tells
  bool continued = false;  // the case went on from the checkpoint an earlier sweep left
};

// The command line (sweep_cases.cpp): throws UsageError naming what is wrong.
Settings parse(const std::vector<std::string>& args);
// Every combination of the axes' values, the last -D varying fastest, with its files.
std::vector<Case> make_cases(const Settings& s);

}  // namespace granule::app::sweep_detail
