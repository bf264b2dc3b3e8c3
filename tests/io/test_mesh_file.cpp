// Mesh files through assimp: STL (ASCII and binary) and OBJ written here, read
// back as vertices and triangles with the scene's scale, rotation and
// translation applied; the defects are counted or refused with the reason.
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "io/mesh_file.hpp"

using namespace granule;
using Catch::Matchers::Contains;

namespace {
std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("granule_mesh_" + name)).string();
}
using Tri = std::array<std::array<float, 3>, 3>;
// The unit cube [0,1]^3 as 12 outward triangles.
std::vector<Tri> cube_triangles() {
  const float c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                       {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<Tri> out;
  for (auto& f : q) {
    auto corner = [&](int k) { return std::array<float, 3>{c[f[k]][0], c[f[k]][1], c[f[k]][2]}; };
    out.push_back({corner(0), corner(1), corner(2)});
    out.push_back({corner(0), corner(2), corner(3)});
  }
  return out;
}
void write_ascii_stl(const std::string& path, const std::vector<Tri>& tris) {
  std::ofstream f(path);
  f << "solid test\n";
  for (auto& t : tris) {
    f << " facet normal 0 0 0\n  outer loop\n";
    for (auto& v : t) f << "   vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
    f << "  endloop\n endfacet\n";
  }
  f << "endsolid test\n";
}
void write_binary_stl(const std::string& path, const std::vector<Tri>& tris) {
  std::ofstream f(path, std::ios::binary);
  char header[80] = {};
  std::strncpy(header, "granule binary test", sizeof header - 1);
  f.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  f.write(reinterpret_cast<const char*>(&n), 4);
  for (auto& t : tris) {
    const float normal[3] = {0, 0, 0};
    f.write(reinterpret_cast<const char*>(normal), 12);
    for (auto& v : t) f.write(reinterpret_cast<const char*>(v.data()), 12);
    const std::uint16_t attr = 0;
    f.write(reinterpret_cast<const char*>(&attr), 2);
  }
}
const std::vector<Tri> square = {Tri{{{0, 0, 0}, {2, 0, 0}, {2, 3, 0}}},
                                 Tri{{{0, 0, 0}, {2, 3, 0}, {0, 3, 0}}}};
}  // namespace

TEST_CASE("mesh file: an ASCII STL cube is 8 vertices, 12 triangles, closed", "[mesh]") {
  const auto path = temp_path("cube_ascii.stl");
  write_ascii_stl(path, cube_triangles());
  io::MeshFileReport r;
  const auto m = io::read_mesh_file(path, {}, r);
  CHECK(m.vertices.size() == 8);
  CHECK(m.triangles.size() == 12);
  CHECK(r.triangles_read == 12);
  CHECK(r.vertices_merged == 28);  // 36 corners in the file
  CHECK(r.open_edges == 0);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.degenerate_removed == 0);
  CHECK(r.warnings(path).empty());
  Eigen::Vector3d lo = m.vertices[0], hi = m.vertices[0];
  for (auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  CHECK(lo == Eigen::Vector3d(0, 0, 0));
  CHECK(hi == Eigen::Vector3d(1, 1, 1));
  std::filesystem::remove(path);
}

TEST_CASE("mesh file: a binary STL square, scaled, rotated and translated", "[mesh]") {
  const auto path = temp_path("square_binary.stl");
  write_binary_stl(path, square);
  io::MeshTransform t;
  t.scale = 1e-3;  // a file in mm
  t.rotation = io::rotation_about({0, 0, 1}, M_PI / 2);
  t.translation = {0.5, 0, -1};
  io::MeshFileReport r;
  const auto m = io::read_mesh_file(path, t, r);
  REQUIRE(m.vertices.size() == 4);
  CHECK(m.triangles.size() == 2);
  CHECK(r.open_edges == 4);
  CHECK(r.warnings(path).size() == 1);
  // The file's corner (2, 3, 0) mm: scaled to (0.002, 0.003, 0), turned a
  // quarter about z to (-0.003, 0.002, 0), moved by (0.5, 0, -1).
  bool found = false;
  for (auto& v : m.vertices)
    if ((v - Eigen::Vector3d(0.497, 0.002, -1)).norm() < 1e-12) found = true;
  CHECK(found);
  for (auto& v : m.vertices) CHECK(v.z() == -1);
  std::filesystem::remove(path);
}

TEST_CASE("mesh file: an OBJ cube of quads is triangulated, Euler angles turn it", "[mesh]") {
  const auto path = temp_path("cube.obj");
  {
    std::ofstream f(path);
    f << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    f << "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";
  }
  io::MeshTransform t;
  t.rotation = io::rotation_xyz(0, 0, M_PI);  // half a turn about z
  io::MeshFileReport r;
  const auto m = io::read_mesh_file(path, t, r);
  CHECK(m.vertices.size() == 8);
  CHECK(m.triangles.size() == 12);
  CHECK(r.open_edges == 0);
  for (auto& v : m.vertices) {
    CHECK(v.x() < 1e-12);
    CHECK(v.y() < 1e-12);
  }
  std::filesystem::remove(path);
}

TEST_CASE(
    "mesh file: a polygon cut into triangles that do not cover it is refused, one cut right "
    "is read",
    "[mesh]") {
  // Area of the triangles read, for the comparison with the polygon's.
  auto area = [](const io::TriangleMesh& m) {
    double sum = 0;
    for (const auto& t : m.triangles) {
      const Eigen::Vector3d a = m.vertices[t[1]] - m.vertices[t[0]],
                            b = m.vertices[t[2]] - m.vertices[t[0]];
      sum += 0.5 * a.cross(b).norm();
    }
    return sum;
  };
  auto read = [&](const std::string& name, const std::string& obj, double& read_area) {
    const auto path = temp_path(name);
    std::ofstream(path) << obj;
    io::MeshFileReport r;
    std::string error;
    try {
      read_area = area(io::read_mesh_file(path, io::MeshTransform{}, r));
    } catch (const InputError& e) {
      error = e.what();
    }
    std::filesystem::remove(path);
    return error;
  };
  double got = 0;
  // An L of area 3 (a 2 x 2 square less a quarter): assimp's cut covers 4. It
  // is found alone and among 400 unit squares (a quarter of a per cent of the
  // file's area more).
  std::string squares;
  for (int k = 0; k < 400; ++k) {
    const double x = 10 + 2 * (k % 20), y = 2 * (k / 20);
    squares +=
        fmt::format("v {} {} 0\nv {} {} 0\nv {} {} 0\nv {} {} 0\nf {} {} {} {}\n", x, y, x + 1, y,
                    x + 1, y + 1, x, y + 1, 7 + 4 * k, 8 + 4 * k, 9 + 4 * k, 10 + 4 * k);
  }
  for (const std::string& more : {std::string(), squares}) {
    const std::string error = read(
        "l_hexagon.obj",
        "v -1 -1 0\nv 1 -1 0\nv 1 0 0\nv 0 0 0\nv 0 1 0\nv -1 1 0\nf 1 2 3 4 5 6\n" + more, got);
    INFO(error);
    if (error.empty()) {
      // A cut that does cover the L (another assimp) is read with its area.
      CHECK(got == Approx(3.0 + (more.empty() ? 0 : 400)).epsilon(1e-12));
    } else {
      CHECK_THAT(error, Contains("l_hexagon.obj") && Contains("face 1 of mesh 1 (6 corners)") &&
                            Contains("export the file with triangles"));
    }
  }
  // A warped quad (one corner raised by a tenth of the side): its triangles have
  // more area than its vector area, yet the cut is right.
  CHECK(read("warped.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.1\nv 0 1 0\nf 1 2 3 4\n", got).empty());
  // A dart (non-convex quad) and a convex hexagon: cut right, read.
  CHECK(read("dart.obj", "v 0 0 0\nv 2 1 0\nv 0 2 0\nv 0.5 1 0\nf 1 2 3 4\n", got).empty());
  CHECK(got == Approx(1.5).epsilon(1e-12));
  CHECK(read("hexagon.obj",
             "v 2 0 0\nv 1 1.5 0\nv -1 1.5 0\nv -2 0 0\nv -1 -1.5 0\nv 1 -1.5 0\n"
             "f 1 2 3 4 5 6\n",
             got)
            .empty());
  CHECK(got == Approx(9.0).epsilon(1e-12));
}

TEST_CASE("mesh file: degenerate triangles are removed and counted", "[mesh]") {
  auto tris = square;
  tris.push_back(Tri{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}});  // three corners on a line
  tris.push_back(Tri{{{0, 0, 0}, {0, 0, 0}, {0, 3, 0}}});  // two corners at one point
  const auto path = temp_path("degenerate.stl");
  write_ascii_stl(path, tris);
  io::MeshFileReport r;
  const auto m = io::read_mesh_file(path, {}, r);
  CHECK(m.triangles.size() == 2);
  CHECK(r.degenerate_removed == 2);
  CHECK(r.triangles_read == 4);
  REQUIRE(r.warnings(path).size() == 2);
  CHECK_THAT(r.warnings(path)[0], Contains("2 degenerate"));
  std::filesystem::remove(path);
}

TEST_CASE("mesh file: a third triangle on an edge makes it non-manifold", "[mesh]") {
  auto tris = square;
  tris.push_back(Tri{{{0, 0, 0}, {2, 3, 0}, {1, 1, 5}}});
  const auto path = temp_path("fin.stl");
  write_ascii_stl(path, tris);
  io::MeshFileReport r;
  io::read_mesh_file(path, {}, r);
  CHECK(r.non_manifold_edges == 1);
  CHECK(r.open_edges == 6);
  std::filesystem::remove(path);
}

TEST_CASE("mesh file: refused with the reason", "[mesh]") {
  io::MeshFileReport r;
  CHECK_THROWS_WITH(io::read_mesh_file(temp_path("absent.stl"), {}, r),
                    Contains("absent.stl") && Contains("does not exist"));
  const auto empty = temp_path("empty.stl");
  write_ascii_stl(empty, {});
  CHECK_THROWS_AS(io::read_mesh_file(empty, {}, r), InputError);
  const auto flat = temp_path("flat.stl");
  write_ascii_stl(flat, {Tri{{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}}});
  CHECK_THROWS_WITH(io::read_mesh_file(flat, {}, r), Contains("no triangles"));
  const auto nan = temp_path("nan.stl");
  write_binary_stl(nan, {Tri{{{0, 0, 0}, {1, 0, 0}, {0, NAN, 0}}}});
  CHECK_THROWS_WITH(io::read_mesh_file(nan, {}, r), Contains("not finite"));
  write_binary_stl(nan, {Tri{{{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}}}});
  CHECK_THROWS_WITH(io::read_mesh_file(nan, {}, r), Contains("not finite"));
  io::MeshTransform bad;
  bad.scale = 0;
  write_ascii_stl(flat, square);
  CHECK_THROWS_WITH(io::read_mesh_file(flat, bad, r), Contains("scale"));
  bad.scale = -1;
  CHECK_THROWS_WITH(io::read_mesh_file(flat, bad, r), Contains("scale"));
  const auto junk = temp_path("junk.stl");
  {
    std::ofstream f(junk);
    f << "this is not a mesh\n";
  }
  CHECK_THROWS_WITH(io::read_mesh_file(junk, {}, r), Contains("junk.stl"));
  for (auto& p : {empty, flat, nan, junk}) std::filesystem::remove(p);
}
