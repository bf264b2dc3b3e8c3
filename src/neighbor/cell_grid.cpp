#include "neighbor/cell_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/errors.hpp"

namespace granule {

namespace {
template <int D>
inline Vec<D> separation(const Vec<D>& a, const Vec<D>& b, const Periodicity& per) {
  Vec<D> d = a - b;
  if (per.on()) d[per.axis] -= per.length * std::nearbyint(d[per.axis] / per.length);
  return d;
}
}  // namespace

template <int D>
void CellGrid<D>::build(const Particles<D>& p, double skin, const Periodicity& per,
                        std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
  const std::size_t n = p.size();
  if (n < 2) return;

  // Split small from large by the median radius.
  scratch_.assign(p.radius.begin(), p.radius.end());
  std::nth_element(scratch_.begin(), scratch_.begin() + n / 2, scratch_.end());
  const double large_threshold = 2.0 * scratch_[n / 2];
  large_.clear();
  double r_small_max = 0;
  Vec<D> lo = Vec<D>::Constant(INFINITY), hi = Vec<D>::Constant(-INFINITY);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.radius[i] > large_threshold) {
      large_.push_back(static_cast<std::uint32_t>(i));
    } else {
      r_small_max = std::max(r_small_max, p.radius[i]);
    }
    lo = lo.cwiseMin(p.position[i]);
    hi = hi.cwiseMax(p.position[i]);
  }
  cell_size_ = 2 * r_small_max + skin;
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(hi[k] - lo[k]))
      throw RunError(fmt::format(
          "the particles are spread over more than any grid can hold (axis {} from {} to {} m): "
          "a particle has escaped or was placed absurdly far away",
          k, lo[k], hi[k]));
  // Keep the grid at most ~2 cells per particle: a run-away particle must not allocate a huge grid.
  const double max_cells = 2.0 * static_cast<double>(n) + 64;
  for (int attempt = 0; attempt < 64; ++attempt) {
    double cells = 1;
    for (int k = 0; k < D; ++k) {
      double extent = (per.on() && k == per.axis) ? per.length : hi[k] - lo[k];
      cells *= std::floor(extent / cell_size_) + 1;
    }
    if (cells <= max_cells) break;
    // Grow the cells by the factor that brings their count to the limit (and a little more).
    cell_size_ *= std::max(1.5, std::pow(cells / max_cells, 1.0 / D));
  }
  origin_ = lo;
  for (int k = 0; k < D; ++k) {
    if (per.on() && k == per.axis) {
      origin_[k] = per.origin;
      // Cells must span the period exactly; fewer than three cannot host a 3-cell stencil.
      dims_[k] = std::max(1, static_cast<int>(std::floor(per.length / cell_size_)));
    } else {
      dims_[k] = static_cast<int>(std::floor((hi[k] - lo[k]) / cell_size_)) + 1;
    }
  }
  std::vector<double> inv_side(D);
  for (int k = 0; k < D; ++k)
    inv_side[k] = (per.on() && k == per.axis) ? dims_[k] / per.length : 1.0 / cell_size_;

  auto coord = [&](const Vec<D>& x, int k) {
    int c = static_cast<int>(std::floor((x[k] - origin_[k]) * inv_side[k]));
    if (per.on() && k == per.axis) {
      c %= dims_[k];
      if (c < 0) c += dims_[k];
      return c;
    }
    return std::clamp(c, 0, dims_[k] - 1);
  };
  auto flat = [&](const std::array<int, D>& c) {
    std::size_t f = 0;
    for (int k = D - 1; k >= 0; --k) f = f * dims_[k] + c[k];
    return f;
  };
  std::size_t total = 1;
  for (int k = 0; k < D; ++k) total *= dims_[k];

  // Counting sort of small particles into cells.
  cell_start_.assign(total + 1, 0);
  particle_cell_.assign(n, UINT32_MAX);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.radius[i] > large_threshold) continue;
    std::array<int, D> c;
    for (int k = 0; k < D; ++k) c[k] = coord(p.position[i], k);
    particle_cell_[i] = static_cast<std::uint32_t>(flat(c));
    ++cell_start_[particle_cell_[i] + 1];
  }
  for (std::size_t c = 0; c < total; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_particles_.resize(cell_start_[total]);
  {
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      if (particle_cell_[i] != UINT32_MAX)
        cell_particles_[fill[particle_cell_[i]]++] = static_cast<std::uint32_t>(i);
  }

  // Is j within reach of a particle at xi with radius ri, and may they meet?
  // Two fixed particles (boundaries, each moved only as the scene sets it), or
  // two ghosts of a distributed run (bit 1), exert nothing on each other here;
  // a fixed particle and a ghost still do.
  const Vec<D>* const x = p.position.data();
  const double* const radius = p.radius.data();
  const std::uint8_t* const fixed = p.fixed.data();
  const bool wraps = per.on();
  auto within_reach = [&](const Vec<D>& xi, double ri, std::uint8_t fi, std::uint32_t j)
      __attribute__((always_inline)) {
    const double reach = ri + radius[j] + skin;
    const Vec<D> d = wraps ? separation<D>(xi, x[j], per) : Vec<D>(xi - x[j]);
    return ((fi & fixed[j]) == 0) & (d.squaredNorm() < reach * reach);
  };
  auto consider = [&](std::uint32_t i, std::uint32_t j) {
    if (within_reach(x[i], radius[i], fixed[i], j)) pairs.emplace_back(i, j);
  };

  // Neighbour cell offsets along each axis, deduplicated when a periodic axis has < 3 cells.
  auto axis_offsets = [&](int k, int c, int reach_cells, std::vector<int>& out) {
    out.clear();
    for (int o = -reach_cells; o <= reach_cells; ++o) {
      int cc = c + o;
      if (per.on() && k == per.axis) {
        cc %= dims_[k];
        if (cc < 0) cc += dims_[k];
      } else if (cc < 0 || cc >= dims_[k]) {
        continue;
      }
      if (std::find(out.begin(), out.end(), cc) == out.end()) out.push_back(cc);
    }
  };

  // Visits every cell in the box of cells around `centre` (reach cells per axis).
  std::array<std::vector<int>, D> ranges;
  auto for_cells = [&](const std::array<int, D>& centre, const std::array<int, D>& reach,
                       auto&& visit) {
    for (int k = 0; k < D; ++k) {
      axis_offsets(k, centre[k], reach[k], ranges[k]);
      if (ranges[k].empty()) return;
    }
    std::array<std::size_t, D> idx{};
    for (;;) {
      std::array<int, D> c;
      for (int k = 0; k < D; ++k) c[k] = ranges[k][idx[k]];
      visit(flat(c));
      int k = 0;
      while (k < D && ++idx[k] == ranges[k].size()) idx[k++] = 0;
      if (k == D) break;
    }
  };

  // small-small: each unordered pair once (j > i). The 3^D cells around each
  // particle's cell are those for_cells visits, in its order (axis 0 fastest),
  // so the pairs come out as from the general stencil; each axis's neighbouring
  // coordinates are listed once per build instead of once per particle.
  std::array<std::vector<std::array<int, 4>>, D> near;  // [0]: count, then the coordinates
  for (int k = 0; k < D; ++k) {
    near[k].resize(static_cast<std::size_t>(dims_[k]));
    std::vector<int> out;
    for (int c = 0; c < dims_[k]; ++c) {
      axis_offsets(k, c, 1, out);
      auto& row = near[k][static_cast<std::size_t>(c)];
      row[0] = static_cast<int>(out.size());
      for (std::size_t q = 0; q < out.size(); ++q) row[q + 1] = out[q];
    }
  }
  // The scan writes every pair it looks at into the next place of `pairs` and
  // keeps it only when it is near: no branch on "j after i" and "near", which
  // the cells' mixed order makes unpredictable. The arrays as local pointers
  // (captured, they would be reloaded after every store); room is made before
  // each cell, for all its particles.
  const std::uint32_t* const start = cell_start_.data();
  const std::uint32_t* const members = cell_particles_.data();
  const std::uint32_t* const cell_of = particle_cell_.data();
  std::size_t kept = pairs.size();
  auto scan_cell = [&](std::uint32_t i, std::size_t cell) __attribute__((always_inline)) {
    const std::uint32_t first = start[cell], last = start[cell + 1];
    if (pairs.size() < kept + (last - first)) pairs.resize(2 * (kept + (last - first)));
    std::pair<std::uint32_t, std::uint32_t>* const out = pairs.data();
    const Vec<D> xi = x[i];
    const double ri = radius[i];
    const std::uint8_t fi = fixed[i];
    for (std::uint32_t s = first; s < last; ++s) {
      const std::uint32_t j = members[s];
      out[kept] = {i, j};
      kept += (j > i) & within_reach(xi, ri, fi, j);
    }
  };
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t own = cell_of[i];
    if (own == UINT32_MAX) continue;
    std::array<int, D> c;
    std::size_t rest = own;
    for (int k = 0; k < D; ++k) {
      c[k] = static_cast<int>(rest % static_cast<std::size_t>(dims_[k]));
      rest /= static_cast<std::size_t>(dims_[k]);
    }
    const auto& n0 = near[0][static_cast<std::size_t>(c[0])];
    const auto& n1 = near[1][static_cast<std::size_t>(c[1])];
    const auto ii = static_cast<std::uint32_t>(i);
    if constexpr (D == 2) {
      for (int b = 1; b <= n1[0]; ++b)
        for (int a = 1; a <= n0[0]; ++a)
          scan_cell(ii, static_cast<std::size_t>(n1[b]) * dims_[0] + n0[a]);
    } else {
      const auto& n2 = near[2][static_cast<std::size_t>(c[2])];
      for (int e = 1; e <= n2[0]; ++e)
        for (int b = 1; b <= n1[0]; ++b) {
          const std::size_t plane = (static_cast<std::size_t>(n2[e]) * dims_[1] + n1[b]) * dims_[0];
          for (int a = 1; a <= n0[0]; ++a) scan_cell(ii, plane + n0[a]);
        }
    }
  }
  pairs.resize(kept);
  // large-small: scan the cells within the large particle's reach.
  for (std::uint32_t i : large_) {
    std::array<int, D> c, reach;
    const double r = p.radius[i] + r_small_max + skin;
    for (int k = 0; k < D; ++k) {
      c[k] = coord(p.position[i], k);
      // At most the grid's width (a radius beyond any grid must not overflow).
      reach[k] = static_cast<int>(std::min<double>(std::ceil(r * inv_side[k]) + 1, dims_[k]));
    }
    for_cells(c, reach, [&](std::size_t cell) {
      for (std::uint32_t s = cell_start_[cell]; s < cell_start_[cell + 1]; ++s)
        consider(i, cell_particles_[s]);
    });
  }
  // large-large: few, so directly.
  for (std::size_t a = 0; a < large_.size(); ++a)
    for (std::size_t b = a + 1; b < large_.size(); ++b) consider(large_[a], large_[b]);
}

template class CellGrid<2>;
template class CellGrid<3>;

}  // namespace granule
