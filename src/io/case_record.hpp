// What `granule sweep` keeps in each case's HDF5 file besides the run itself:
// the scalars the scene reported (/results, written by sim:result) are read
// back for the summary, and a /sweep_case group is added once the case's run
// has ended successfully. That group is the mark of a finished case: a file
// whose writer was killed half-way never has it, so a rerun of the sweep
// runs that case again. Every failure throws std::runtime_error naming the
// file.
#pragma once

#include <map>
#include <optional>
#include <string>

namespace granule::io {

struct CaseRecord {
  std::string key;          // the case's parameter values, "name=value;..." (which case it is)
  int rank = 0;             // the MPI rank that ran it (0 without MPI)
  double wall_seconds = 0;  // of the whole `granule run`
  std::string finished;     // ISO 8601 time, UTC
  // source_digest() of the scene that ran (empty in records of older
  // versions): a case of an edited scene is not a finished case of it.
  std::string scene_digest;
};

// A digest of a scene's text (FNV-1a, 64 bits, as 16 hex digits).
std::string source_digest(const std::string& text);

// The numeric attributes of /results; empty when the scene reported none.
std::map<std::string, double> read_results(const std::string& path);

// The /sweep_case record, or nothing when the file is missing, unreadable or has none.
std::optional<CaseRecord> read_case_record(const std::string& path);

// Adds (or replaces) /sweep_case; creates the file if the scene wrote none.
void write_case_record(const std::string& path, const CaseRecord& record);

}  // namespace granule::io
