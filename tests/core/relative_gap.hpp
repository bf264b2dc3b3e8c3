// How far apart two runs' arrays are: the largest difference, relative to the
// largest value (the batched and per-contact paths' comparisons).
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace granule::test {

inline double relative_gap(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double largest = 0, gap = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    largest = std::max(largest, std::abs(a[k]));
    gap = std::max(gap, std::abs(a[k] - b[k]));
  }
  REQUIRE(largest > 0);
  return gap / largest;
}

}  // namespace granule::test
