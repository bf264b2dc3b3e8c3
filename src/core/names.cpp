#include "core/names.hpp"

#include <algorithm>
#include <cctype>

namespace granule {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

// Case is ignored: "Young" for "young" or "al2o3" for "Al2O3" is the name meant, at
// distance 0, whatever else is one edit away. Of names equally near, the first in
// byte order, so that the hint does not follow the order the candidates were
// collected in (a Lua table's, which changes from run to run); a name that
// shares no letter in place with the one typed (distance the longer one's
// length) is no hint.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(3, name.size() / 3) + 1;
  const std::string key = lower(name);
  for (const auto& c : candidates) {
    std::size_t d = edit_distance(key, lower(c));
    if (d >= std::max(name.size(), c.size())) continue;
    if (d < best_distance || (d == best_distance && c < best)) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace granule
