// A rigid polyline as a 2D wall: a chain of points joined by straight
// segments or circular arcs, open or closed, and the contacts of a disk with
// it. The plane's counterpart of MeshSurface (mesh_surface.hpp), with the
// same contact rule.
//
// Contact by closest feature. Each segment near the disk gives its closest
// point to the centre: in its interior (on the line or on the arc) or at one
// of its two end points. The disk's contacts are the local minima of the
// distance to the whole chain, found locally: an end point is shared with
// the neighbouring segment, and of the two the nearer (then the lower index)
// owns it, so a disk on a straight or convex chain has one contact whose
// point and normal move continuously as it rolls across a joint, while the
// two segments of a concave corner each hold their own interior contact (the
// elimination of mesh_surface.hpp, Kremmer & Favier 2001, in the plane).
//
// An arc is given per segment by a signed radius: positive bulges to the left
// of the segment's direction (from its first point to its second), negative
// to the right; |radius| >= half the chord, and the arc is the shorter of the
// two on that circle (at most a half circle). Everything is in the
// polyline's own frame; mesh_set.hpp moves it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/mesh_surface.hpp"

namespace granule {

// A polyline as declared: segment k joins points k and k + 1 (and, when
// closed, the last segment joins the last point to the first); radius[k] is
// segment k's signed arc radius, 0 for a straight segment.
struct Polyline {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> radius;  // one per segment (empty: all straight)
  bool closed = false;
};

// One contact of a disk with a polyline, in the polyline's frame.
struct PolylineHit {
  Eigen::Vector2d point;                    // the closest point of the chain
  Eigen::Vector2d normal;                   // unit, from the chain to the centre
  double distance = 0;                      // centre to `point`
  std::uint32_t triangle = 0;               // the segment (named as MeshHit's, for shared code)
  MeshFeature feature = MeshFeature::face;  // face: a segment's interior; vertex: a point
  std::uint32_t element = 0;                // the point's index (the segment's for an interior)
  double curvature_radius = 0;              // an arc interior's |radius|; 0: flat
  bool concave = false;                     // the centre on the arc's centre side
};

class PolylineSurface {
 public:
  // The most contacts one disk can have with one polyline at once.
  static constexpr int max_hits = MeshSurface::max_hits;

  // Throws InputError naming the point or segment at fault: fewer than 2
  // points, a point that is not finite, a segment of zero length, an arc
  // radius that is not finite or is less than half the chord.
  explicit PolylineSurface(Polyline line);

  std::size_t segment_count() const { return seg_.size(); }
  std::size_t point_count() const { return x_.size(); }
  bool closed() const { return closed_; }
  const std::vector<Eigen::Vector2d>& points() const { return x_; }
  double arc_radius(std::size_t s) const { return radius_[s]; }
  // An arc's centre (meaningless for a straight segment).
  const Eigen::Vector2d& arc_center(std::size_t s) const { return center_[s]; }
  // The segment's end points' indices.
  std::array<std::uint32_t, 2> ends(std::size_t s) const { return seg_[s]; }
  // The largest distance of a point of the chain from `point` (how far a turn moves it).
  double reach_from(const Eigen::Vector2d& point) const;
  // Points along the chain, arcs divided into pieces of at most `degrees`
  // (drawing and output): each segment's pieces in order, the chain's points
  // included, the first point repeated at the end of a closed chain.
  std::vector<Eigen::Vector2d> outline(double degrees = 5) const;

  // Whether x lies inside a closed chain (false for an open one): inside the
  // polygon of its chords, changed wherever an arc's bulge (the part of its
  // disk between chord and arc) covers x. Outside the chain's bounding box at
  // the cost of four comparisons.
  bool encloses(const Eigen::Vector2d& x) const;
  // The point of the whole chain nearest x (its normal from the chain to x).
  PolylineHit nearest(const Eigen::Vector2d& x) const;

  // The closest point of segment s to x.
  PolylineHit closest(std::uint32_t s, const Eigen::Vector2d& x) const;
  // Whether any segment lies within `within` of x (neighbour lists).
  bool near(const Eigen::Vector2d& x, double within) const;
  // The contacts of a disk (centre x) with the chain: every closest point
  // nearer than `within`, after elimination, nearest first (at most
  // max_hits). Returns their number; `tested` (if given) gets the segments
  // examined.
  int contacts(const Eigen::Vector2d& x, double radius, double within, PolylineHit* out,
               std::int64_t* tested = nullptr) const;

 private:
  std::vector<Eigen::Vector2d> x_;
  std::vector<std::array<std::uint32_t, 2>> seg_;
  std::vector<double> radius_;
  std::vector<Eigen::Vector2d> center_;  // arcs' centres
  std::vector<Eigen::Vector2d> apex_;    // arcs' unit directions from the centre to the middle
  std::vector<double> cos_half_;         // arcs: cosine of half the angle they span
  // Each segment lies within its chord's half length of the chord's middle
  // (an arc of at most a half circle does): a cheap test before closest().
  std::vector<Eigen::Vector2d> middle_;
  std::vector<double> half_chord_;
  // The segments that end at each point (before it) and start there (after
  // it); -1 where the open chain ends.
  std::vector<std::array<std::int64_t, 2>> around_;
  Eigen::Vector2d lo_, hi_;  // a box holding every segment (arcs by their chord's circle)
  double seam_ = 0;          // 1e-6 of the box's diagonal (as MeshSurface's)
  bool closed_ = false;
};

}  // namespace granule
