// The XDMF descriptor: wall shapes are where the walls are; the XML points at
// the snapshot datasets. (tests/io/check_xdmf.py checks real files against
// the HDF5 they describe.)
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../geometry/mesh_helpers.hpp"
#include "engine/simulation.hpp"
#include "io/mesh_file.hpp"
#include "io/xdmf.hpp"

using namespace granule;

TEST_CASE("xdmf: file name beside the HDF5 file", "[xdmf]") {
  CHECK(io::xdmf_path_for("out.h5") == "out.xmf");
  CHECK(io::xdmf_path_for("dir/run.1.h5") == "dir/run.1.xmf");
  CHECK(io::xdmf_path_for("plain") == "plain.xmf");
  CHECK(io::xdmf_walls_path_for("out.h5") == "out_walls.xmf");
  CHECK(io::xdmf_walls_path_for("dir/run.1.h5") == "dir/run.1_walls.xmf");
}

TEST_CASE("xdmf: a 2D drum is a closed polygon on its circle, a plane a segment on its line",
          "[xdmf]") {
  WallSpec drum;
  drum.name = "drum";
  drum.type = WallType::cylinder;
  drum.center = {0.001, 0.002, 0};
  drum.radius = 0.01;
  WallSpec floor;
  floor.name = "floor";
  floor.type = WallType::plane;
  floor.point = {0, -0.005, 0};
  floor.normal = {0, 2, 0};
  auto shapes = io::wall_shapes({drum, floor}, 2, {-0.01, 0.01, -0.01, 0.01, 0, 0});
  REQUIRE(shapes.size() == 2);
  const auto& c = shapes[0];
  CHECK(c.topology == "Polyline");
  CHECK(c.connectivity.front() == c.connectivity.back());  // closed
  for (std::size_t k = 0; k < c.points.size(); k += 3)
    CHECK(std::hypot(c.points[k] - 0.001, c.points[k + 1] - 0.002) == Approx(0.01));
  const auto& f = shapes[1];
  REQUIRE(f.points.size() == 6);
  CHECK(f.points[1] == Approx(-0.005));
  CHECK(f.points[4] == Approx(-0.005));
  CHECK(std::abs(f.points[3] - f.points[0]) > 0.02);  // spans the extent
}

TEST_CASE("xdmf: a 3D cylinder is a tube spanning the extent along its axis", "[xdmf]") {
  WallSpec tube;
  tube.name = "tube";
  tube.type = WallType::cylinder;
  tube.axis = {1, 0, 0};
  tube.radius = 0.002;
  auto shapes = io::wall_shapes({tube}, 3, {-0.01, 0.02, -0.01, 0.01, -0.01, 0.01});
  const auto& t = shapes[0];
  CHECK(t.topology == "Quadrilateral");
  CHECK(t.connectivity.size() % 4 == 0);
  double x_min = 1, x_max = -1;
  for (std::size_t k = 0; k < t.points.size(); k += 3) {
    CHECK(std::hypot(t.points[k + 1], t.points[k + 2]) == Approx(0.002));
    x_min = std::min(x_min, t.points[k]);
    x_max = std::max(x_max, t.points[k]);
  }
  CHECK(x_min == Approx(-0.01));
  CHECK(x_max == Approx(0.02));
}

TEST_CASE("xdmf: snapshots become a temporal collection of Polyvertex grids", "[xdmf]") {
  auto dir = std::filesystem::temp_directory_path() / "granule_xdmf_test";
  std::filesystem::create_directories(dir);
  io::XdmfIndex index((dir / "run.h5").string());
  CHECK(index.path() == (dir / "run.xmf").string());
  io::XdmfSnapshot s;
  s.group = "/snapshots/000001";
  s.time = 0.25;
  s.count = 7;
  s.dimension = 2;
  index.add(s);
  s.group = "/snapshots/000002";
  s.step = 1;
  s.count = 0;  // an empty snapshot has no grid: XDMF has no empty Polyvertex
  index.add(s);
  index.flush();
  CHECK(index.written());
  std::ifstream in(index.path());
  std::stringstream text;
  text << in.rdbuf();
  const std::string x = text.str();
  CHECK(x == index.text());
  CHECK_THAT(x, Catch::Contains("CollectionType=\"Temporal\""));
  CHECK_THAT(x, Catch::Contains("<Time Value=\"0.25\"/>"));
  CHECK_THAT(x, Catch::Contains("TopologyType=\"Polyvertex\" NumberOfElements=\"7\""));
  CHECK_THAT(x, Catch::Contains("GeometryType=\"XY\""));
  CHECK_THAT(x, Catch::Contains(">run.h5:/snapshots/000001/position<"));
  CHECK_THAT(x, !Catch::Contains("000002"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("xdmf: the walls go to a file of their own, the particles' file holds particles only",
          "[xdmf]") {
  auto dir = std::filesystem::temp_directory_path() / "granule_xdmf_walls_test";
  std::filesystem::create_directories(dir);
  io::XdmfIndex index((dir / "run.h5").string());
  CHECK(index.walls_path() == (dir / "run_walls.xmf").string());
  WallSpec floor;
  floor.name = "floor";
  floor.type = WallType::plane;
  floor.point = {0, 0, 0};
  floor.normal = {0, 0, 1};
  io::XdmfSnapshot s;
  s.group = "/snapshots/000000";
  s.count = 3;
  s.dimension = 3;
  s.walls = io::wall_shapes({floor}, 3, {-0.01, 0.01, -0.01, 0.01, 0, 0.01});
  index.add(s);
  auto read = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  };
  const std::string particles = read(index.path());
  const std::string walls = read(index.walls_path());
  CHECK_THAT(particles, !Catch::Contains("wall_floor"));
  CHECK_THAT(particles, !Catch::Contains("Quadrilateral"));
  CHECK_THAT(walls, Catch::Contains("Grid Name=\"wall_floor\""));
  CHECK_THAT(walls, Catch::Contains("Quadrilateral"));
  CHECK_THAT(walls, !Catch::Contains("Polyvertex"));
  // A later index of the same name without walls removes the stale walls file.
  io::XdmfIndex bare((dir / "run.h5").string());
  s.walls.clear();
  bare.add(s);
  CHECK(!std::filesystem::exists(index.walls_path()));
  std::filesystem::remove_all(dir);
}

TEST_CASE("xdmf: a mesh wall is its triangles where the mesh is now", "[xdmf][mesh]") {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  sim.set_contact("p", "w", "linear",
                  {{"k_normal", 1000}, {"restitution", 0.5}, {"friction", 0.3}});
  sim.set_contact("p", "p", "linear",
                  {{"k_normal", 1000}, {"restitution", 0.5}, {"friction", 0.3}});
  MeshWallSpec m;
  m.name = "fan";
  m.material = 1;
  m.angular_velocity = 2;  // about z through the origin
  io::TriangleMesh fan = test::fan_disk(0.01, 12);
  io::MeshFileReport report;
  io::clean_mesh(fan, report);
  sim.add_mesh_wall(m, fan);
  ParticleSpec p;
  p.position = {0, 0, 0.005};
  p.radius = 1e-3;
  p.material = 0;
  sim.add_particle(p);
  sim.prepare();
  auto shapes_now = [&] {
    std::vector<WallSpec> walls{sim.wall(0)};
    auto shapes = io::wall_shapes(walls, 3, {-0.01, 0.01, -0.01, 0.01, -0.01, 0.01});
    io::add_mesh_shapes(shapes, sim.mesh_views());
    return shapes;
  };
  auto before = shapes_now();
  REQUIRE(before.size() == 1);
  CHECK(before[0].topology == "Triangle");
  CHECK(before[0].nodes_per_element == 3);
  CHECK(before[0].connectivity.size() == 3 * 12);
  REQUIRE(before[0].points.size() == 3 * 13);
  // Vertex 1 of the fan starts at (R, 0, 0) and turns with the mesh.
  CHECK(before[0].points[3] == Approx(0.01));
  sim.advance(1000);
  const double angle = 2 * sim.time();
  auto after = shapes_now();
  CHECK(after[0].points[3] == Approx(0.01 * std::cos(angle)).margin(1e-12));
  CHECK(after[0].points[4] == Approx(0.01 * std::sin(angle)).margin(1e-12));
  CHECK(angle > 0.01);
}

TEST_CASE("xdmf: a second snapshot of one step supersedes the first in the index", "[xdmf]") {
  // The final state written after a callback changed the last step's particles:
  // one grid per time, the later one's.
  auto dir = std::filesystem::temp_directory_path() / "granule_xdmf_same_step";
  std::filesystem::create_directories(dir);
  io::XdmfIndex index((dir / "run.h5").string());
  io::XdmfSnapshot s;
  s.dimension = 3, s.count = 3, s.step = 0, s.time = 0, s.group = "/snapshots/000000";
  index.add(s);
  s.step = 1000, s.time = 0.01, s.group = "/snapshots/000001";
  index.add(s);
  s.count = 2, s.group = "/snapshots/000002";  // the same step again
  index.add(s);
  const std::string x = index.text();
  CHECK(index.snapshots().size() == 2);
  CHECK_THAT(x, Catch::Contains(">run.h5:/snapshots/000002/position<"));
  CHECK_THAT(x, !Catch::Contains("000001"));
  // A later one of no particles (a callback removed them all) has no grid: the
  // step's grid with particles stays, rather than the step losing both.
  s.count = 0, s.group = "/snapshots/000003";
  index.add(s);
  const std::string y = index.text();
  CHECK(index.snapshots().size() == 2);
  CHECK_THAT(y, Catch::Contains(">run.h5:/snapshots/000002/position<"));
  CHECK_THAT(y, Catch::Contains("<Time Value=\"0.01\"/>"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("xdmf: many snapshots, the files written at flush() hold them all", "[xdmf]") {
  // Rewrites are spaced out by their cost (xdmf.hpp); whatever was skipped, a
  // flush writes every snapshot added, walls that moved as a temporal
  // collection, and the files on disk always hold a whole document.
  auto dir = std::filesystem::temp_directory_path() / "granule_xdmf_many";
  std::filesystem::create_directories(dir);
  io::XdmfIndex index((dir / "run.h5").string());
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  };
  for (int k = 0; k < 3000; ++k) {
    io::XdmfSnapshot s;
    s.dimension = 3, s.count = 5, s.step = k, s.time = 1e-3 * k;
    s.group = fmt::format("/snapshots/{:06d}", k);
    io::XdmfShape plate;
    plate.name = "plate", plate.topology = "Quadrilateral", plate.nodes_per_element = 4;
    plate.points = {0, 0, 1e-4 * k, 1, 0, 1e-4 * k, 1, 1, 1e-4 * k, 0, 1, 1e-4 * k};
    plate.connectivity = {0, 1, 2, 3};
    s.walls = {plate};
    index.add(s);
    if (k == 0) CHECK(index.written());  // the first is written at once
    if (k % 500 == 0) {
      const std::string x = read(index.path());
      CHECK(x.rfind("</Xdmf>\n") == x.size() - 8);  // a whole document
    }
  }
  index.flush();
  CHECK(index.written());
  const std::string x = read(index.path()), walls = read(index.walls_path());
  CHECK(x == index.text());
  CHECK(walls == index.walls_text());
  std::size_t grids = 0;
  for (std::size_t at = x.find("<Time "); at != std::string::npos; at = x.find("<Time ", at + 1))
    ++grids;
  CHECK(grids == 3000);
  CHECK_THAT(x, Catch::Contains(">run.h5:/snapshots/002999/position<"));
  CHECK_THAT(walls, Catch::Contains("CollectionType=\"Temporal\""));
  CHECK_THAT(walls, Catch::Contains("<Grid Name=\"002999\""));
  std::filesystem::remove_all(dir);
}
