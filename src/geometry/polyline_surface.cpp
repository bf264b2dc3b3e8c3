#include "geometry/polyline_surface.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace granule {

namespace {
// The left normal of d, unnormalised.
Eigen::Vector2d left_of(const Eigen::Vector2d& d) {
  return Eigen::Vector2d(-d.y(), d.x());
}
}  // namespace

PolylineSurface::PolylineSurface(Polyline line) : x_(std::move(line.points)), closed_(line.closed) {
  if (x_.size() < 2)
    throw InputError(fmt::format("points: a polyline needs at least 2 points, got {}", x_.size()));
  for (std::size_t k = 0; k < x_.size(); ++k)
    if (!x_[k].allFinite())
      throw InputError(
          fmt::format("points[{}] = {{{}, {}}} is not finite", k + 1, x_[k].x(), x_[k].y()));
  const std::size_t n = x_.size();
  const std::size_t segments = closed_ ? n : n - 1;
  if (!line.radius.empty() && line.radius.size() != segments)
    throw InputError(fmt::format("a polyline of {} segments was given {} arc radii", segments,
                                 line.radius.size()));
  radius_ = line.radius.empty() ? std::vector<double>(segments, 0.0) : std::move(line.radius);
  seg_.resize(segments);
  center_.assign(segments, Eigen::Vector2d::Zero());
  apex_.assign(segments, Eigen::Vector2d::Zero());
  cos_half_.assign(segments, 1.0);
  middle_.resize(segments);
  half_chord_.resize(segments);
  around_.assign(n, {-1, -1});
  for (std::size_t s = 0; s < segments; ++s) {
    const auto a = static_cast<std::uint32_t>(s), b = static_cast<std::uint32_t>((s + 1) % n);
    seg_[s] = {a, b};
    around_[a][1] = static_cast<std::int64_t>(s);
    around_[b][0] = static_cast<std::int64_t>(s);
    const Eigen::Vector2d d = x_[b] - x_[a];
    const double chord2 = d.squaredNorm();
    if (!std::isfinite(chord2))
      throw InputError(
          fmt::format("segment {} (points {} and {}) is too long: its length "
                      "overflows",
                      s + 1, a + 1, b + 1));
    if (!(chord2 > 0))
      throw InputError(
          fmt::format("segment {} (points {} and {}) has zero length", s + 1, a + 1, b + 1));
    middle_[s] = 0.5 * (x_[a] + x_[b]);
    half_chord_[s] = 0.5 * std::sqrt(chord2);
    const double R = radius_[s];
    if (!std::isfinite(R))
      throw InputError(fmt::format("arc radius of segment {} is {}: not finite", s + 1, R));
    if (R == 0) continue;
    // A half circle's end points computed by trigonometry lie a few ulps further
    // apart than 2R: within 1e-12 the arc is a half circle.
    if (std::abs(R) < half_chord_[s] * (1 - 1e-12))
      throw InputError(fmt::format(
          "arc radius of segment {} is {} m: its magnitude must be at least half the chord, {} m",
          s + 1, R, half_chord_[s]));
    // The centre lies off the chord's middle, on the side away from the
    // bulge, at c k where k = sqrt(R^2 / c^2 - 1/4) (written so that a
    // quarter circle's centre comes out exact).
    const double k = std::sqrt(std::max(0.0, R * R / chord2 - 0.25));
    const double side = R > 0 ? 1.0 : -1.0;
    center_[s] = middle_[s] - side * k * left_of(d);
    apex_[s] = side * left_of(d) / std::sqrt(chord2);
    cos_half_[s] = k * std::sqrt(chord2) / std::abs(R);
    if (!center_[s].allFinite() || !std::isfinite(cos_half_[s]))
      throw InputError(fmt::format(
          "arc radius of segment {} is {} m: too large to place its centre (a straight segment "
          "has radius 0)",
          s + 1, R));
  }
  lo_ = hi_ = x_[0];
  for (std::size_t s = 0; s < seg_.size(); ++s) {  // a segment lies within its chord's circle
    lo_ = lo_.cwiseMin(middle_[s] - Eigen::Vector2d::Constant(half_chord_[s]));
    hi_ = hi_.cwiseMax(middle_[s] + Eigen::Vector2d::Constant(half_chord_[s]));
  }
  seam_ = 1e-6 * (hi_ - lo_).norm();
}

double PolylineSurface::reach_from(const Eigen::Vector2d& point) const {
  double most = 0;
  for (const auto& v : x_) most = std::max(most, (v - point).norm());
  for (std::size_t s = 0; s < seg_.size(); ++s)  // an arc lies within |R| of its centre
    if (radius_[s] != 0) most = std::max(most, (center_[s] - point).norm() + std::abs(radius_[s]));
  return most;
}

std::vector<Eigen::Vector2d> PolylineSurface::outline(double degrees) const {
  std::vector<Eigen::Vector2d> out{x_[seg_[0][0]]};
  for (std::size_t s = 0; s < seg_.size(); ++s) {
    const Eigen::Vector2d &a = x_[seg_[s][0]], &b = x_[seg_[s][1]];
    if (radius_[s] != 0) {
      const Eigen::Vector2d ua = a - center_[s];
      const double span = 2 * std::acos(std::clamp(cos_half_[s], -1.0, 1.0));
      const double sense = ua.x() * apex_[s].y() - ua.y() * apex_[s].x() >= 0 ? 1.0 : -1.0;
      const int pieces = std::max(1, static_cast<int>(std::ceil(span / (degrees * M_PI / 180))));
      for (int j = 1; j < pieces; ++j) {
        const double t = sense * span * j / pieces;
        out.push_back(center_[s] + Eigen::Vector2d(std::cos(t) * ua.x() - std::sin(t) * ua.y(),
                                                   std::sin(t) * ua.x() + std::cos(t) * ua.y()));
      }
    }
    out.push_back(b);
  }
  return out;
}

// An interior point of a line is found by projection on its normal (as the
// analytic plane's distance is), an arc's along the ray from its centre (as
// the cylinder's is), and an end point is the stored point itself, so the two
// segments at a joint find bit-identical points there.
PolylineHit PolylineSurface::closest(std::uint32_t s, const Eigen::Vector2d& x) const {
  const auto [ia, ib] = seg_[s];
  const Eigen::Vector2d &a = x_[ia], &b = x_[ib];
  const Eigen::Vector2d d = b - a;
  PolylineHit h;
  h.triangle = s;
  auto at_point = [&](std::uint32_t v) {
    h.feature = MeshFeature::vertex;
    h.element = v;
    h.point = x_[v];
    const Eigen::Vector2d away = x - h.point;
    h.distance = away.norm();
    h.normal = h.distance > 0 ? Eigen::Vector2d(away / h.distance)
                              : Eigen::Vector2d(left_of(d).normalized());
    return h;
  };
  h.feature = MeshFeature::face;
  h.element = s;
  const double R = radius_[s];
  if (R == 0) {
    const double along = (x - a).dot(d) / d.squaredNorm();
    if (!(along > 0)) return at_point(ia);
    if (!(along < 1)) return at_point(ib);
    const Eigen::Vector2d n = left_of(d) / d.norm();
    const double above = (x - a).dot(n);
    h.point = x - above * n;
    h.distance = std::abs(above);
    h.normal = above < 0 ? Eigen::Vector2d(-n) : n;
    return h;
  }
  const Eigen::Vector2d u = x - center_[s];
  const double rho = u.norm(), radius = std::abs(R);
  h.curvature_radius = radius;
  if (!(rho > 0)) {  // at the centre: every point of the arc is as near; take its middle
    h.point = center_[s] + radius * apex_[s];
    h.distance = radius;
    h.normal = -apex_[s];
    h.concave = true;
    return h;
  }
  if (!(u.dot(apex_[s]) >= rho * cos_half_[s]))  // outside the arc's wedge: an end is nearest
    return (x - a).squaredNorm() <= (x - b).squaredNorm() ? at_point(ia) : at_point(ib);
  const Eigen::Vector2d u_hat = u / rho;
  h.point = center_[s] + radius * u_hat;
  h.concave = rho < radius;
  h.distance = h.concave ? radius - rho : rho - radius;
  h.normal = h.concave ? Eigen::Vector2d(-u_hat) : u_hat;
  return h;
}

PolylineHit PolylineSurface::nearest(const Eigen::Vector2d& x) const {
  PolylineHit best = closest(0, x);
  for (std::uint32_t s = 1; s < seg_.size(); ++s) {
    const PolylineHit h = closest(s, x);
    if (h.distance < best.distance) best = h;
  }
  return best;
}

bool PolylineSurface::encloses(const Eigen::Vector2d& x) const {
  if (!closed_) return false;
  if (!(x.x() >= lo_.x() && x.x() <= hi_.x() && x.y() >= lo_.y() && x.y() <= hi_.y())) return false;
  bool inside = false;
  for (std::size_t s = 0; s < seg_.size(); ++s) {
    const Eigen::Vector2d &a = x_[seg_[s][0]], &b = x_[seg_[s][1]];
    // The chord crosses the ray from x along +x (half-open in y, so a vertex
    // on the ray's height is counted once).
    if ((a.y() > x.y()) != (b.y() > x.y())) {
      const double at = a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (at > x.x()) inside = !inside;
    }
    if (radius_[s] != 0) {
      const Eigen::Vector2d d = b - a;
      const double side = d.x() * (x.y() - a.y()) - d.y() * (x.x() - a.x());
      const bool on_bulge_side = radius_[s] > 0 ? side > 0 : side < 0;
      if (on_bulge_side && (x - center_[s]).norm() < std::abs(radius_[s])) inside = !inside;
    }
  }
  return inside;
}

bool PolylineSurface::near(const Eigen::Vector2d& x, double within) const {
  for (std::uint32_t s = 0; s < seg_.size(); ++s)
    if ((x - middle_[s]).norm() < within + half_chord_[s] && closest(s, x).distance < within)
      return true;
  return false;
}

int PolylineSurface::contacts(const Eigen::Vector2d& x, double radius, double within,
                              PolylineHit* out, std::int64_t* tested) const {
  thread_local std::vector<PolylineHit> hits;
  hits.clear();
  std::int64_t examined = 0;
  for (std::uint32_t s = 0; s < seg_.size(); ++s) {
    if (!((x - middle_[s]).norm() < within + half_chord_[s])) continue;
    ++examined;
    const PolylineHit h = closest(s, x);
    if (h.distance < within) hits.push_back(h);
  }
  if (tested) *tested += examined;
  // Nearest first; ties by segment index, so the owner of a shared point does
  // not depend on the order the segments were examined in.
  auto before = [](const PolylineHit& p, const PolylineHit& q) {
    return p.distance < q.distance || (p.distance == q.distance && p.triangle < q.triangle);
  };
  std::sort(hits.begin(), hits.end(), before);
  int count = 0;
  // Two closest points closer than this are one contact (a joint of a
  // straight chain found by both its segments, rounded differently).
  const double same = 1e-6 * radius;
  // A segment passing this near a joint touches it (an end placed on another
  // segment up to a rounding): as MeshSurface::contacts.
  const double touching = std::min(0.1 * radius, std::max(1e-3 * radius, seam_));
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const PolylineHit& h = hits[i];
    if (h.feature == MeshFeature::vertex) {
      // A joint belongs to both segments there: the other is at least as
      // near, and if it is nearer (or as near with a lower index) it owns
      // the contact, or this point is no minimum at all. So does any nearer
      // segment that passes through the point without being joined to it.
      bool owned = false;
      for (std::size_t k = 0; k < i && !owned; ++k) {
        const std::uint32_t other = hits[k].triangle;
        if (other == h.triangle) continue;
        owned = other == around_[h.element][0] || other == around_[h.element][1] ||
                closest(other, h.point).distance <= touching;
      }
      if (owned) continue;
    }
    bool repeated = false;
    for (int k = 0; k < count && !repeated; ++k) repeated = (out[k].point - h.point).norm() <= same;
    if (repeated) continue;
    out[count++] = h;
    if (count == max_hits) break;
  }
  return count;
}

}  // namespace granule
