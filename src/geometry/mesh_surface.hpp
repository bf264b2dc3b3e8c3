// A rigid triangle mesh as a wall: its triangles, the topology the contact
// needs (the triangles around each edge and vertex), a cell grid of the
// triangles, and the contacts of a sphere with it.
//
// Contact by closest feature. Each triangle near the sphere gives its closest
// point to the centre, on its face, one of its edges or one of its corners.
// The sphere's contacts are the local minima of the distance to the whole
// surface, found without a global search: a triangle whose closest point lies
// on an edge or corner shares that point with the other triangles around it,
// and one of those (the nearest, then the lowest index) owns the contact, so
// a particle on a flat or convex patch has one contact whose point and normal
// move continuously as it rolls from face to edge to the next face (the
// elimination of Kremmer & Favier 2001 and of LIGGGHTS's mesh walls, written
// from the distance-minimum argument). Two faces meeting at a concave edge
// each hold their own face contact: two distinct minima, two contacts.
// Everything is in the mesh's own frame (the file's after the scene's scale,
// rotation and translation); mesh_set.hpp moves it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/triangles.hpp"

namespace granule {

enum class MeshFeature : std::uint8_t { face, edge, vertex };

// One contact of a sphere with a mesh, in the mesh's frame.
struct MeshHit {
  Eigen::Vector3d point;   // the closest point of the surface
  Eigen::Vector3d normal;  // unit, from the surface to the centre
  double distance = 0;     // centre to `point`
  std::uint32_t triangle = 0;
  MeshFeature feature = MeshFeature::face;
  std::uint32_t element = 0;  // the edge's or the vertex's index (the triangle's for a face)
};

// The triangles in cubic cells: each triangle is listed in every cell it
// comes within half a cell diagonal of, so a query visits the few cells a
// sphere overlaps and the triangles listed there.
struct TriangleGrid {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double cell = 0;
  std::array<std::int64_t, 3> n{0, 0, 0};
  std::vector<std::uint32_t> start, items;
  bool built() const { return cell > 0; }
};

class MeshSurface {
 public:
  // The most contacts one sphere can have with one mesh (a sphere in a corner
  // of three faces has three).
  static constexpr int max_hits = 4;

  explicit MeshSurface(Triangles mesh);

  std::size_t triangle_count() const { return tri_.size(); }
  std::size_t vertex_count() const { return x_.size(); }
  const std::vector<Eigen::Vector3d>& vertices() const { return x_; }
  const std::vector<std::array<std::uint32_t, 3>>& triangles() const { return tri_; }
  const Eigen::Vector3d& triangle_normal(std::size_t t) const { return normal_[t]; }
  Eigen::Vector3d lower() const { return lo_; }
  Eigen::Vector3d upper() const { return hi_; }
  // The largest distance of a vertex from `point` (how far a turn moves it).
  double reach_from(const Eigen::Vector3d& point) const;

  // (Re)builds the cell grid for queries of radius up to `reach` (cells at
  // least 2 reach wide, so a query spans at most two cells along each axis,
  // and no more than about 4 cells per triangle or 2^22 in all).
  void build_grid(double reach);
  const TriangleGrid& grid() const { return grid_; }
  std::size_t edge_count() const { return edge_vertex_.size(); }

  // The closest point of triangle t to x.
  MeshHit closest(std::uint32_t t, const Eigen::Vector3d& x) const;
  // Whether any triangle lies within `within` of x (neighbour lists).
  bool near(const Eigen::Vector3d& x, double within) const;
  // Two contacts of one sphere whose normals are less than this far apart
  // (degrees, in [0, 90); 0: none) are one, the nearer: the facets of a
  // surface meshed from a smooth concave curve (a drum, a cone, a bowl) meet
  // at shallow folds, where a sphere would otherwise press on both faces with
  // two springs in parallel.
  void set_flat_angle(double degrees);
  double flat_angle() const { return flat_angle_; }
  static constexpr double default_flat_angle = 20;

  // The contacts of a sphere (centre x) with the surface: every closest point
  // nearer than `within`, after elimination, nearest first (at most max_hits).
  // Returns their number; `tested` (if given) gets the triangles examined.
  int contacts(const Eigen::Vector3d& x, double radius, double within, MeshHit* out,
               std::int64_t* tested = nullptr) const;

 private:
  // The triangles listed in the cells a sphere of radius `within` at x overlaps,
  // each once, in increasing order.
  void candidates(const Eigen::Vector3d& x, double within, std::vector<std::uint32_t>& out) const;
  // Whether triangle t is one of those around h's edge or corner.
  bool shares(std::uint32_t t, const MeshHit& h) const;
  // Whether triangle t touches h's point, not joined to it (a seam, a T-junction).
  bool touches(std::uint32_t t, const MeshHit& h, double touching) const;
  std::vector<Eigen::Vector3d> x_;
  std::vector<std::array<std::uint32_t, 3>> tri_;
  std::vector<Eigen::Vector3d> normal_;
  std::vector<std::array<std::uint32_t, 3>> tri_edge_;     // edge k joins corners k and k+1
  std::vector<std::array<std::uint32_t, 2>> edge_vertex_;  // lower vertex index first
  std::vector<std::uint32_t> edge_start_, edge_tris_;      // triangles around each edge
  std::vector<std::uint32_t> vertex_start_, vertex_tris_;  // triangles around each vertex
  Eigen::Vector3d lo_, hi_;
  TriangleGrid grid_;
  double flat_angle_ = default_flat_angle;
  double flat_cos_ = 0;  // cos(flat_angle_); above 1 when no two contacts are merged
  double seam_ = 0;      // 1e-6 of the mesh's diagonal: its single-precision rounding, about
};

}  // namespace granule
