#include "app/sweep_ranks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#ifdef GRANULE_HAVE_MPI
namespace granule::app::sweep_detail {

namespace {

std::string clean_line(std::string text) {
  std::replace(text.begin(), text.end(), '\t', ' ');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

}  // namespace

std::string encode(const Outcome& o) {
  std::string text = fmt::format("{}\t{}\t{}\t{:.17g}\t{}\t{}\n", o.index, int(o.status), o.rank,
                                 o.wall_seconds, o.continued ? 1 : 0, clean_line(o.error));
  for (const auto& [name, value] : o.results) text += fmt::format("{}\t{:.17g}\n", name, value);
  return text;
}

Outcome decode(const std::string& text) {
  Outcome o;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::istringstream head(line);
  std::string field;
  std::getline(head, field, '\t');
  o.index = std::stoul(field);
  std::getline(head, field, '\t');
  o.status = static_cast<Status>(std::stoi(field));
  std::getline(head, field, '\t');
  o.rank = std::stoi(field);
  std::getline(head, field, '\t');
  o.wall_seconds = std::stod(field);
  std::getline(head, field, '\t');
  o.continued = field == "1";
  std::getline(head, o.error);
  while (std::getline(in, line)) {
    auto tab = line.find('\t');
    if (tab != std::string::npos) o.results[line.substr(0, tab)] = std::stod(line.substr(tab + 1));
  }
  return o;
}

}  // namespace granule::app::sweep_detail
#endif  // GRANULE_HAVE_MPI
