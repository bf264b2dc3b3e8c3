// granule sweep's summary of all cases (sweep_summary.cpp): one row per case
// with its values, status, results, rank, wall time, file and error.
#pragma once

#include <string>
#include <vector>

#include "app/sweep_types.hpp"

namespace granule::app::sweep_detail {

struct Summary {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

// The table of every case; fills `result_names` with the results' columns.
Summary tabulate(const Settings& s, const std::vector<Case>& cases,
                 const std::vector<Outcome>& outcomes, std::vector<std::string>& result_names);
void write_csv(const std::string& path, const Summary& t);
void write_markdown(const std::string& path, const Settings& s, const Summary& t);
// The finished cases as the series /sweep and the whole table as CSV text in /sweep_table.
void write_h5(const std::string& path, const Settings& s, const std::vector<Case>& cases,
              const std::vector<Outcome>& outcomes, const std::vector<std::string>& result_names,
              const std::string& csv_text);

}  // namespace granule::app::sweep_detail
