// The batched and per-contact paths' runs compared (test_batch.cpp,
// test_wall_batch.cpp): how far apart two arrays are, and one logged
// contact's forces and normal in each.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "engine/simulation_base.hpp"

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

// The same contact as two runs logged it: normal and tangential forces within
// 1e-9 of the largest normal force, the normals within 1e-9. True when it
// carries a tangential force.
inline bool check_record_forces(const ContactRecord& a, const ContactRecord& b,
                                double largest_force) {
  CHECK(std::abs(a.normal_force - b.normal_force) <= 1e-9 * largest_force);
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(std::abs(a.tangential_force[axis] - b.tangential_force[axis]) <= 1e-9 * largest_force);
    CHECK(std::abs(a.normal[axis] - b.normal[axis]) <= 1e-9);
  }
  return std::hypot(a.tangential_force[0], a.tangential_force[1], a.tangential_force[2]) > 0;
}

}  // namespace granule::test
