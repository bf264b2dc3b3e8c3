#include "core/names.hpp"

#include <algorithm>
#include <cctype>

namespace granule {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  // Three rows: the one two characters back holds the cost before a swap.
  std::vector<std::size_t> before(b.size() + 1), last(b.size() + 1), row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) last[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      row[j] =
          std::min({last[j] + 1, row[j - 1] + 1, last[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, last);
    std::swap(last, row);
  }
  return last[b.size()];
}

namespace {
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
}  // namespace

// Case is ignored: "Young" for "young" or "al2o3" for "Al2O3" is the name meant, at
// distance 0, whatever else is one edit away. Of names equally near, the one that
// keeps more of the typed name's start and end ("radis": "radius" before
// "radii"), then the first in byte order, so that the hint does not follow the
// order the candidates were collected in (a Lua table's, which changes from run
// to run); a name that shares no letter in place with the one typed (distance
// the longer one's length) is no hint.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(3, name.size() / 3) + 1, best_kept = 0;
  const std::string key = lower(name);
  // Letters the two share at their start and at their end.
  auto kept = [&key](const std::string& c) {
    std::size_t front = 0, back = 0;
    const std::size_t n = std::min(key.size(), c.size());
    while (front < n && key[front] == c[front]) ++front;
    while (back < n - front && key[key.size() - 1 - back] == c[c.size() - 1 - back]) ++back;
    return front + back;
  };
  for (const auto& c : candidates) {
    const std::string lc = lower(c);
    std::size_t d = edit_distance(key, lc);
    if (d >= std::max(name.size(), c.size())) continue;
    const std::size_t k = kept(lc);
    if (d < best_distance ||
        (!best.empty() && d == best_distance && (k > best_kept || (k == best_kept && c < best)))) {
      best_kept = k;
      best_distance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace granule
