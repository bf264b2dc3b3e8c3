#include "parallel/decomposition.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace granule::parallel {

namespace {

template <int D>
struct Bisector {
  const std::vector<Vec<D>>& points;
  const std::vector<double>& weights;
  const std::vector<std::int64_t>& ids;
  Decomposition<D>& out;

  double weight(std::size_t k) const { return weights.empty() ? 1.0 : weights[k]; }

  // Splits `box` (holding the points `members`) among ranks [first, first + count).
  void split(const Box<D>& box, std::vector<std::size_t> members, int first, int count) {
    double total = 0;
    for (std::size_t k : members) total += weight(k);
    if (count == 1) {
      out.boxes[first] = box;
      out.rank_weight[first] = total;
      return;
    }
    int axis = 0;
    for (int a = 1; a < D; ++a)
      if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
    const int left = count / 2;
    // Order along the axis, ties by id: the same cut whatever order the points came in.
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      if (points[a][axis] != points[b][axis]) return points[a][axis] < points[b][axis];
      return ids[a] < ids[b];
    });
    const double target = total * left / count;
    double below = 0;
    std::size_t split_at = 0;  // members [0, split_at) go left
    while (split_at < members.size() && below + weight(members[split_at]) <= target) {
      below += weight(members[split_at]);
      ++split_at;
    }
    // The one point that straddles the target goes to the side it unbalances less.
    if (split_at < members.size() &&
        std::abs(below + weight(members[split_at]) - target) < std::abs(below - target)) {
      below += weight(members[split_at]);
      ++split_at;
    }
    double position;
    if (members.empty()) {
      position = box.lo[axis] + (box.hi[axis] - box.lo[axis]) * left / count;
    } else if (split_at == 0) {
      position = 0.5 * (box.lo[axis] + points[members[0]][axis]);
    } else if (split_at == members.size()) {
      position = 0.5 * (points[members.back()][axis] + box.hi[axis]);
    } else {
      position = 0.5 * (points[members[split_at - 1]][axis] + points[members[split_at]][axis]);
    }
    // Every point must fall on the side the sort gave it under the box test
    // (lo <= x < hi). Neighbours that share a coordinate (a lattice) cannot be
    // parted: the cut goes below them all. A midpoint of two adjacent doubles may
    // round onto the lower one: the cut goes to the upper.
    if (split_at > 0 && split_at < members.size()) {
      const double below_x = points[members[split_at - 1]][axis];
      const double above_x = points[members[split_at]][axis];
      if (below_x == above_x) {
        position = above_x;
        while (split_at > 0 && points[members[split_at - 1]][axis] == position) --split_at;
      } else if (!(position > below_x && position <= above_x)) {
        position = above_x;
      }
    }
    position = std::clamp(position, box.lo[axis], box.hi[axis]);
    out.cuts.push_back(Cut{first, count, left, axis, position});
    Box<D> low = box, high = box;
    low.hi[axis] = position;
    high.lo[axis] = position;
    std::vector<std::size_t> upper(members.begin() + static_cast<std::ptrdiff_t>(split_at),
                                   members.end());
    members.resize(split_at);
    split(low, std::move(members), first, left);
    split(high, std::move(upper), first + left, count - left);
  }
};

}  // namespace

template <int D>
Decomposition<D> bisect(const Box<D>& domain, const std::array<bool, D>& periodic, int ranks,
                        const std::vector<Vec<D>>& points, const std::vector<double>& weights,
                        const std::vector<std::int64_t>& ids) {
  if (ranks < 1) throw std::invalid_argument(fmt::format("decomposition: {} ranks", ranks));
  if (ids.size() != points.size() || (!weights.empty() && weights.size() != points.size()))
    throw std::invalid_argument("decomposition: points, weights and ids differ in length");
  for (int a = 0; a < D; ++a)
    if (!(domain.hi[a] > domain.lo[a]))
      throw std::invalid_argument(
          fmt::format("decomposition: the domain is empty along axis {} ({} to {} m)", a,
                      domain.lo[a], domain.hi[a]));
  for (double w : weights)
    if (!(w >= 0) || !std::isfinite(w))
      throw std::invalid_argument(fmt::format("decomposition: a point's weight is {}", w));
  Decomposition<D> d;
  d.domain = domain;
  d.periodic = periodic;
  d.boxes.resize(static_cast<std::size_t>(ranks));
  d.rank_weight.assign(static_cast<std::size_t>(ranks), 0.0);
  std::vector<std::size_t> members(points.size());
  std::iota(members.begin(), members.end(), std::size_t{0});
  Bisector<D>{points, weights, ids, d}.split(domain, std::move(members), 0, ranks);
  return d;
}

template <int D>
Vec<D> wrap(const Decomposition<D>& d, Vec<D> x) {
  for (int a = 0; a < D; ++a) {
    if (!d.periodic[a]) continue;
    const double length = d.domain.hi[a] - d.domain.lo[a];
    x[a] -= length * std::floor((x[a] - d.domain.lo[a]) / length);
    if (x[a] >= d.domain.hi[a]) x[a] = d.domain.lo[a];  // rounding at the upper face
  }
  return x;
}

template <int D>
int Decomposition<D>::owner(const Vec<D>& x) const {
  const Vec<D> w = wrap(*this, x);
  // Down the cut tree: each cut sends x to one of its two halves.
  int first = 0, count = ranks();
  for (const Cut& c : cuts) {
    if (c.first != first || c.count != count) continue;
    if (w[c.axis] < c.position) {
      count = c.left;
    } else {
      first += c.left;
      count -= c.left;
    }
    if (count == 1) break;
  }
  return first;
}

template <int D>
double Decomposition<D>::imbalance() const {
  double total = 0, largest = 0;
  for (double w : rank_weight) total += w, largest = std::max(largest, w);
  return total > 0 ? largest * ranks() / total : 1.0;
}

template <int D>
std::string Decomposition<D>::describe() const {
  static const char* axis_name = "xyz";
  std::string text = fmt::format("rcb, {} boxes, imbalance {:.3f}", ranks(), imbalance());
  if (!cuts.empty()) {
    text += "; cuts";
    for (const Cut& c : cuts) text += fmt::format(" {}={:.6g}", axis_name[c.axis], c.position);
  }
  return text;
}

template struct Decomposition<2>;
template struct Decomposition<3>;
template Decomposition<2> bisect<2>(const Box<2>&, const std::array<bool, 2>&, int,
                                    const std::vector<Vec<2>>&, const std::vector<double>&,
                                    const std::vector<std::int64_t>&);
template Decomposition<3> bisect<3>(const Box<3>&, const std::array<bool, 3>&, int,
                                    const std::vector<Vec<3>>&, const std::vector<double>&,
                                    const std::vector<std::int64_t>&);
template Vec<2> wrap<2>(const Decomposition<2>&, Vec<2>);
template Vec<3> wrap<3>(const Decomposition<3>&, Vec<3>);

}  // namespace granule::parallel
