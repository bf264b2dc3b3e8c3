// Triangle meshes from CAD files (STL ASCII and binary, OBJ, and whatever
// else assimp reads) as plain arrays, placed in the scene: scaled, rotated
// about the origin, then translated, so the vertices are in metres after the
// scale. What is wrong with a file is either refused with the reason (no
// triangles, a non-finite vertex, a bad scale, an unreadable file) or, where
// harmless for a wall, counted and reported (degenerate triangles removed,
// open and non-manifold edges).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/triangles.hpp"

namespace granule::io {

using TriangleMesh = granule::Triangles;

// x_scene = rotation * (scale * x_file) + translation.
struct MeshTransform {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

struct MeshFileReport {
  std::size_t triangles_read = 0;
  std::size_t degenerate_removed = 0;  // zero area, or two corners at one point
  std::size_t vertices_merged = 0;     // corners at the same point joined (STL repeats them)
  std::size_t open_edges = 0;          // edges of one triangle only (a mesh that is not closed)
  std::size_t non_manifold_edges = 0;  // edges of three triangles or more
  // One line per harmless defect found, for the scene's warnings.
  std::vector<std::string> warnings(const std::string& path) const;
};

// Rotation matrices for the Lua options: about a unit axis by an angle, and
// Euler angles about x, then y, then z (fixed axes), in radians.
Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double radians);
Eigen::Matrix3d rotation_xyz(double rx, double ry, double rz);

// Reads `path`; throws InputError naming the file and the reason.
TriangleMesh read_mesh_file(const std::string& path, const MeshTransform& transform,
                            MeshFileReport& report);

// Joins corners at the same point, removes degenerate triangles and counts
// open and non-manifold edges (the part of read_mesh_file after the reading).
void clean_mesh(TriangleMesh& mesh, MeshFileReport& report);

}  // namespace granule::io
