// Which ranks need a copy (a ghost) of a particle: every rank whose box lies
// within the interaction reach of the particle's centre, or of one of its
// periodic images, which are ghosts too (on its own rank when the domain is one
// box wide along a periodic axis). The reach is the largest centre distance at
// which two particles can interact before the next list rebuild: twice the
// largest radius, plus the skin, plus the adhesive reach of JKR contacts.
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <vector>

#include "parallel/decomposition.hpp"

namespace granule::parallel {

template <int D>
struct GhostTarget {
  int rank = 0;
  Vec<D> shift = Vec<D>::Zero();  // m: the ghost sits at x + shift (a periodic image)
};

// The periodic shifts (k L along each periodic axis, k in -1, 0, 1) in a fixed
// order; the zero shift first.
template <int D>
std::vector<Vec<D>> periodic_shifts(const Decomposition<D>& d) {
  std::vector<Vec<D>> shifts{Vec<D>::Zero()};
  for (int a = 0; a < D; ++a) {
    if (!d.periodic[a]) continue;
    const double length = d.domain.hi[a] - d.domain.lo[a];
    const std::size_t n = shifts.size();
    for (int k : {-1, 1})
      for (std::size_t s = 0; s < n; ++s) {
        Vec<D> v = shifts[s];
        v[a] += k * length;
        shifts.push_back(v);
      }
  }
  return shifts;
}

// A reach of half a periodic length or more would need images beyond the
// nearest: refused with the axis named.
template <int D>
void check_reach(const Decomposition<D>& d, double reach) {
  if (!(reach >= 0))
    throw std::invalid_argument(fmt::format("ghosts: interaction reach {} m", reach));
  for (int a = 0; a < D; ++a)
    if (d.periodic[a] && 2 * reach >= d.domain.hi[a] - d.domain.lo[a])
      throw std::invalid_argument(fmt::format(
          "ghosts: the interaction reach {} m is half the periodic length along axis {} ({} m) or "
          "more",
          reach, a, d.domain.hi[a] - d.domain.lo[a]));
}

// Appends to `out` the ranks (with shifts) that need a ghost of a particle at x
// owned by `owner`, in a fixed order (by shift, then by rank). `shifts` is
// periodic_shifts(d).
template <int D>
void ghost_targets(const Decomposition<D>& d, const std::vector<Vec<D>>& shifts, const Vec<D>& x,
                   double reach, int owner, std::vector<GhostTarget<D>>& out) {
  // Deep inside its own box, away from every face by more than the reach: no ghost.
  const Box<D>& own = d.boxes[static_cast<std::size_t>(owner)];
  bool inner = true;
  for (int a = 0; a < D && inner; ++a) inner = x[a] - own.lo[a] > reach && own.hi[a] - x[a] > reach;
  if (inner) return;
  for (const Vec<D>& shift : shifts) {
    const Vec<D> image = x + shift;
    const bool moved = !shift.isZero();
    for (int r = 0; r < d.ranks(); ++r) {
      if (r == owner && !moved) continue;
      if (d.boxes[static_cast<std::size_t>(r)].distance(image) < reach) out.push_back({r, shift});
    }
  }
}

}  // namespace granule::parallel
