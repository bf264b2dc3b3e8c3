// Small meshes built in memory for the mesh-wall tests.
#pragma once

#include <cmath>

#include "io/mesh_file.hpp"

namespace granule::test {

// A flat square [-L, L]^2 at height z, cut into n x n squares of two
// triangles each (diagonals along +x+y), normal +z.
inline io::TriangleMesh flat_grid(double L, int n, double z = 0) {
  io::TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.vertices.emplace_back(-L + 2 * L * i / n, -L + 2 * L * j / n, z);
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// A disk of radius R at z = 0 as a fan of n triangles about its centre.
inline io::TriangleMesh fan_disk(double R, int n) {
  io::TriangleMesh m;
  m.vertices.emplace_back(0, 0, 0);
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    m.vertices.emplace_back(R * std::cos(a), R * std::sin(a), 0);
  }
  for (int k = 0; k < n; ++k)
    m.triangles.push_back(
        {0, static_cast<std::uint32_t>(1 + k), static_cast<std::uint32_t>(1 + (k + 1) % n)});
  return m;
}

// An L of two squares meeting along the y axis: the floor z = 0 (x in
// [0, L]) and the side x = 0 (z in [0, L]), y in [-L, L]: a concave edge.
inline io::TriangleMesh corner(double L) {
  io::TriangleMesh m;
  m.vertices = {{0, -L, 0}, {0, L, 0}, {L, L, 0}, {L, -L, 0}, {0, L, L}, {0, -L, L}};
  m.triangles = {{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {0, 4, 5}};
  return m;
}

// A roof: two squares meeting along the y axis at z = 0, sloping down by
// `slope` to either side: a convex edge.
inline io::TriangleMesh roof(double L, double slope) {
  io::TriangleMesh m;
  m.vertices = {{0, -L, 0},          {0, L, 0},           {L, L, -slope * L},
                {L, -L, -slope * L}, {-L, L, -slope * L}, {-L, -L, -slope * L}};
  m.triangles = {{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {0, 4, 5}};
  return m;
}

}  // namespace granule::test
