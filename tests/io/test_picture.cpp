// Pictures: decode the PNG we wrote (zlib, no library of ours) and look at the
// pixels where the particles and walls must be.
#include <zlib.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "engine/simulation_base.hpp"
#include "io/picture.hpp"

using namespace granule;

namespace {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::array<int, 3> at(int x, int y) const {
    const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
};

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return (std::uint32_t(b[at]) << 24) | (std::uint32_t(b[at + 1]) << 16) |
         (std::uint32_t(b[at + 2]) << 8) | b[at + 3];
}

// A minimal PNG reader for 8-bit RGB images with filter 0, checking every CRC.
Image read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)), {});
  REQUIRE(b.size() > 8);
  REQUIRE(
      std::equal(b.begin(), b.begin() + 8,
                 std::vector<std::uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}.begin()));
  Image img;
  std::vector<std::uint8_t> packed;
  for (std::size_t at = 8; at + 12 <= b.size();) {
    std::uint32_t len = be32(b, at);
    std::string type(b.begin() + at + 4, b.begin() + at + 8);
    uLong crc = crc32(crc32(0L, Z_NULL, 0), &b[at + 4], len + 4);
    REQUIRE(crc == be32(b, at + 8 + len));
    if (type == "IHDR") {
      img.width = static_cast<int>(be32(b, at + 8));
      img.height = static_cast<int>(be32(b, at + 12));
      REQUIRE(b[at + 16] == 8);
      REQUIRE(b[at + 17] == 2);
    } else if (type == "IDAT") {
      packed.insert(packed.end(), b.begin() + at + 8, b.begin() + at + 8 + len);
    }
    at += 12 + len;
  }
  std::vector<std::uint8_t> raw((static_cast<std::size_t>(img.width) * 3 + 1) * img.height);
  uLongf size = raw.size();
  REQUIRE(uncompress(raw.data(), &size, packed.data(), packed.size()) == Z_OK);
  REQUIRE(size == raw.size());
  for (int y = 0; y < img.height; ++y) {
    REQUIRE(raw[y * (img.width * 3 + 1)] == 0);
    auto row = raw.begin() + y * (img.width * 3 + 1) + 1;
    img.rgb.insert(img.rgb.end(), row, row + img.width * 3);
  }
  return img;
}

std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("granule_picture_" + name)).string();
}

// Two particles of two materials inside a drum, in a 2 cm square view of 200 px:
// 10^4 px per metre, so (x, y) m lands on pixel (100 + 1e4 x, 100 - 1e4 y).
std::unique_ptr<SimulationBase> scene(int dimension) {
  auto sim = make_simulation(dimension);
  sim->add_material({"glass", 2500});
  sim->add_material({"steel", 7800});
  WallSpec drum;
  drum.name = "drum";
  drum.type = WallType::cylinder;
  drum.material = 1;
  drum.radius = 0.009;
  sim->add_wall(drum);
  ParticleSpec a;
  a.position = {0.005, 0, 0};
  a.velocity = {1, 0, 0};
  a.radius = 1e-3;
  a.material = 0;
  sim->add_particle(a);
  ParticleSpec b;
  b.position = {-0.005, 0.005, 0};
  b.radius = 1e-3;
  b.material = 1;
  sim->add_particle(b);
  return sim;
}

io::PictureOptions options(const std::string& file) {
  io::PictureOptions o;
  o.path = file;
  o.width = 200;
  o.view = std::array<double, 4>{-0.01, 0.01, -0.01, 0.01};
  o.legend = false;
  return o;
}

bool near(const std::array<int, 3>& c, std::array<int, 3> want, int tolerance = 2) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(c[k] - want[k]) > tolerance) return false;
  return true;
}

}  // namespace

TEST_CASE("picture: PNG pixels show particles by material and the drum", "[picture]") {
  auto sim = scene(2);
  auto o = options(temp("material.png"));
  o.color_by = io::ColorBy::material;
  auto info = io::write_picture(*sim, o);
  CHECK(info.width == 200);
  CHECK(info.height == 200);
  CHECK(info.particles == 2);
  Image img = read_png(o.path);
  REQUIRE(img.width == 200);
  REQUIRE(img.height == 200);
  CHECK(near(img.at(150, 100), {31, 119, 180}));   // glass: the first category colour
  CHECK(near(img.at(50, 50), {255, 127, 14}));     // steel: the second
  CHECK(near(img.at(100, 100), {255, 255, 255}));  // empty middle
  CHECK(near(img.at(2, 2), {255, 255, 255}));      // outside the drum
  auto ring = img.at(190, 100);                    // the drum at 0.009 m = 90 px
  CHECK(ring[0] < 100);
  CHECK(near(img.at(162, 100), {255, 255, 255}));  // just beyond the 10 px particle
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: speed colours span the viridis scale from 0 to the fastest", "[picture]") {
  auto sim = scene(2);
  auto o = options(temp("speed.png"));
  auto info = io::write_picture(*sim, o);
  CHECK(info.value_min == 0);
  CHECK(info.value_max == Approx(1.0));
  Image img = read_png(o.path);
  CHECK(near(img.at(150, 100), {253, 231, 37}));  // fastest: the top of the scale
  CHECK(near(img.at(50, 50), {68, 1, 84}));       // at rest: the bottom
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: in 3D the highest particle is drawn on top", "[picture]") {
  auto sim = make_simulation(3);
  sim->add_material({"low", 1000});
  sim->add_material({"high", 1000});
  for (int m : {1, 0}) {  // the higher one is added first: order must come from z
    ParticleSpec p;
    p.position = {0, 0, m == 1 ? 0.002 : 0.0};
    p.radius = 1e-3;
    p.material = m;
    sim->add_particle(p);
  }
  auto o = options(temp("depth.png"));
  o.color_by = io::ColorBy::material;
  io::write_picture(*sim, o);
  Image img = read_png(o.path);
  CHECK(near(img.at(100, 100), {255, 127, 14}));  // material 1, the higher
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: SVG holds the same discs, bad options are refused", "[picture]") {
  auto sim = scene(2);
  auto o = options(temp("scene.svg"));
  o.legend = true;
  io::write_picture(*sim, o);
  std::ifstream in(o.path);
  std::stringstream text;
  text << in.rdbuf();
  CHECK_THAT(text.str(), Catch::Contains("<circle cx=\"150.00\" cy=\"100.00\" r=\"10.000\""));
  CHECK_THAT(text.str(), Catch::Contains("speed"));
  std::filesystem::remove(o.path);

  auto bad = options(temp("x.gif"));
  CHECK_THROWS_AS(io::write_picture(*sim, bad), InputError);
  bad = options(temp("x.png"));
  bad.width = 5;
  CHECK_THROWS_AS(io::write_picture(*sim, bad), InputError);
  bad = options(temp("x.png"));
  bad.range = std::array<double, 2>{1, 1};
  CHECK_THROWS_AS(io::write_picture(*sim, bad), InputError);
  CHECK_THROWS_AS(io::parse_color_by("colour"), InputError);
}

namespace {

// Particles of materials 0, 1, 2, ... at the given 3D positions, radius 1 mm.
std::unique_ptr<SimulationBase> spheres(const std::vector<std::array<double, 3>>& at) {
  auto sim = make_simulation(3);
  for (std::size_t k = 0; k < at.size(); ++k) sim->add_material({"m" + std::to_string(k), 1000});
  for (std::size_t k = 0; k < at.size(); ++k) {
    ParticleSpec p;
    p.position = at[k];
    p.radius = 1e-3;
    p.material = static_cast<int>(k);
    sim->add_particle(p);
  }
  return sim;
}

const std::array<int, 3> colour0{31, 119, 180}, colour1{255, 127, 14}, colour2{44, 160, 44};

}  // namespace

TEST_CASE("picture: the x-z and y-z views put each axis where it belongs", "[picture]") {
  // A on +x, B on +z, C on +y.
  auto sim = spheres({{0.005, 0, 0}, {0, 0, 0.005}, {0, 0.005, 0}});
  auto o = options(temp("xz.png"));
  o.color_by = io::ColorBy::material;
  o.projection = io::Projection::xz;  // x right, z up
  io::write_picture(*sim, o);
  Image img = read_png(o.path);
  CHECK(near(img.at(150, 100), colour0));
  CHECK(near(img.at(100, 50), colour1));
  CHECK(near(img.at(100, 100), colour2));
  o.projection = io::Projection::yz;  // y right, z up
  io::write_picture(*sim, o);
  img = read_png(o.path);
  CHECK(near(img.at(100, 100), colour0));
  CHECK(near(img.at(100, 50), colour1));
  CHECK(near(img.at(150, 100), colour2));
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: in the side views the particle nearer the viewer is on top", "[picture]") {
  auto o = options(temp("side_depth.png"));
  o.color_by = io::ColorBy::material;
  // x-z looks along +y: the smaller y is nearer. Added far first, then near.
  auto along_y = spheres({{0, 0.001, 0}, {0, -0.001, 0}});
  o.projection = io::Projection::xz;
  io::write_picture(*along_y, o);
  CHECK(near(read_png(o.path).at(100, 100), colour1));
  // y-z looks along -x: the larger x is nearer. Added near first, then far.
  auto along_x = spheres({{0.001, 0, 0}, {-0.001, 0, 0}});
  o.projection = io::Projection::yz;
  io::write_picture(*along_x, o);
  CHECK(near(read_png(o.path).at(100, 100), colour0));
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: a slab draws only the particles whose centre lies in it", "[picture]") {
  auto sim = spheres({{0, -0.004, 0}, {0, 0, 0}, {0, 0.004, 0}, {0.004, 0.0009, 0}});
  auto o = options(temp("slab.png"));
  o.projection = io::Projection::xz;
  o.slab = std::array<double, 2>{-0.001, 0.001};
  auto info = io::write_picture(*sim, o);
  CHECK(info.particles == 2);
  o.slab = std::array<double, 2>{0.003, 0.005};
  CHECK(io::write_picture(*sim, o).particles == 1);
  o.projection = io::Projection::xy;  // along z: all four centres at z = 0
  o.slab = std::array<double, 2>{-0.0005, 0.0005};
  CHECK(io::write_picture(*sim, o).particles == 4);
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: in perspective the nearer of two equal spheres is larger and brighter",
          "[picture]") {
  // The camera on -y looking at the origin; sphere 0 nearer (y = -0.02), sphere 1
  // farther (y = +0.02), each off to one side.
  auto sim = spheres({{-0.004, -0.02, 0}, {0.004, 0.02, 0}});
  io::PictureOptions o;
  o.path = temp("perspective.png");
  o.width = 400;
  o.legend = false;
  o.color_by = io::ColorBy::material;
  o.projection = io::Projection::perspective;
  o.eye = std::array<double, 3>{0, -0.05, 0};
  o.target = std::array<double, 3>{0, 0, 0};
  auto info = io::write_picture(*sim, o);
  CHECK(info.particles == 2);
  Image img = read_png(o.path);
  // Widths of the two discs along the middle row, and their centre colours.
  const int row = img.height / 2;
  int first = -1, last = -1, first2 = -1, last2 = -1;
  std::array<int, 3> white_px{255, 255, 255};
  for (int x = 0; x < img.width; ++x) {
    const bool ink = !near(img.at(x, row), white_px, 30);
    if (ink && x < img.width / 2) {
      if (first < 0) first = x;
      last = x;
    }
    if (ink && x >= img.width / 2) {
      if (first2 < 0) first2 = x;
      last2 = x;
    }
  }
  REQUIRE(first >= 0);
  REQUIRE(first2 >= 0);
  const int near_width = last - first, far_width = last2 - first2;
  // Pinhole: the drawn size goes as 1 / distance (0.03 m against 0.07 m).
  CHECK(near_width == Approx(far_width * 0.07 / 0.03).epsilon(0.12));
  auto near_colour = img.at((first + last) / 2, row),
       far_colour = img.at((first2 + last2) / 2, row);
  CHECK(near(near_colour, colour0, 3));  // nearest: full colour
  CHECK(far_colour[0] + far_colour[1] + far_colour[2] <
        0.7 * (colour1[0] + colour1[1] + colour1[2]));  // farthest: shaded to 55 %
  std::filesystem::remove(o.path);
}

TEST_CASE("picture: projections that do not apply are refused with the reason", "[picture]") {
  auto flat = scene(2);
  auto o = options(temp("refused.png"));
  o.projection = io::Projection::xz;
  CHECK_THROWS_WITH(io::write_picture(*flat, o), Catch::Contains("needs a 3D scene"));
  auto sim = spheres({{0, 0, 0}});
  o.projection = io::Projection::perspective;
  o.slab = std::array<double, 2>{0, 1};
  CHECK_THROWS_WITH(io::write_picture(*sim, o), Catch::Contains("slab is for the xy"));
  o.slab.reset();
  o.projection = io::Projection::xy;
  o.eye = std::array<double, 3>{0, 0, 1};
  CHECK_THROWS_WITH(io::write_picture(*sim, o), Catch::Contains("eye and target are for"));
  o.eye.reset();
  o.slab = std::array<double, 2>{1, 0};
  CHECK_THROWS_WITH(io::write_picture(*sim, o), Catch::Contains("finite lo < hi"));
  CHECK_THROWS_WITH(io::parse_projection("side"), Catch::Contains("xy, xz, yz, perspective"));
}
