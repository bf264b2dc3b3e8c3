// A triangle mesh as plain arrays: what a mesh file gives (io/mesh_file.hpp)
// and a mesh wall is built from (mesh_surface.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace granule {

struct Triangles {
  std::vector<Eigen::Vector3d> vertices;                // m
  std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into vertices
};

}  // namespace granule
