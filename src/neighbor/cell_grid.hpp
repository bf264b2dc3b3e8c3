// Candidate pairs by cell lists: every pair of particles whose surfaces are
// closer than `skin`. Cost is linear in N for any size distribution:
//  - "small" particles (all but the few much larger than the median) are
//    binned in cells of side 2 r_small_max + skin and paired through the
//    3^D neighbouring cells;
//  - each "large" particle (radius above twice the median) scans the cells its
//    own reach covers, and large ones are paired with each other directly.
// So one 80:1 particle does not inflate the cells of thousands of small ones.
// An optional periodic axis wraps the cell grid and uses the minimum image.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/particles.hpp"

namespace granule {

struct Periodicity {
  int axis = -1;      // -1: none
  double origin = 0;  // lower bound of the periodic box along `axis`, m
  double length = 0;  // m
  bool on() const { return axis >= 0; }
  // A coordinate along `axis` moved into the box [origin, origin + length] (a
  // rounding below origin comes back as origin + length).
  double into_box(double c) const { return c - length * std::floor((c - origin) / length); }
  // Whether into_box keeps c's place: within a million periods of the box (farther,
  // round-off in the wrap loses it).
  bool wraps_exactly(double c) const { return std::abs(c - origin) <= 1e6 * length; }
  // The minimum image of a separation d along the periodic axis, for |d| < 1.5
  // length (positions are kept inside the box, so any two differ by less than
  // one length). Branches instead of nearbyint, which is a library call on
  // baseline x86-64 and would make every hot loop spill its registers.
  double wrap(double d) const {
    const double half = 0.5 * length;
    if (d > half) return d - length;
    if (d < -half) return d + length;
    return d;
  }
};

template <int D>
class CellGrid {
 public:
  // Appends to `pairs` each (i, j), i != j, with |x_i - x_j| < r_i + r_j + skin,
  // skipping pairs of two fixed particles. Each pair appears once.
  void build(const Particles<D>& p, double skin, const Periodicity& periodic,
             std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);

  double cell_size() const { return cell_size_; }
  std::size_t large_count() const { return large_.size(); }

 private:
  double cell_size_ = 0;
  Vec<D> origin_;
  std::array<int, D> dims_{};
  std::vector<std::uint32_t> cell_start_, cell_particles_, particle_cell_;
  std::vector<std::uint32_t> large_;
  std::vector<double> scratch_;
};

}  // namespace granule
