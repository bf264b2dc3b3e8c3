// The closest-feature contact of a sphere with a triangle mesh, checked
// against distances worked out by hand, and the triangle grid's economy.
#include <catch2/catch.hpp>
#include <cmath>

#include "geometry/mesh_surface.hpp"
#include "mesh_helpers.hpp"

using namespace granule;
using Eigen::Vector3d;

TEST_CASE("mesh surface: closest point on a face, an edge and a corner", "[mesh]") {
  Triangles one;
  one.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.triangles = {{0, 1, 2}};
  MeshSurface s(one);
  MeshHit h = s.closest(0, {0.2, 0.3, 0.5});
  CHECK(h.feature == MeshFeature::face);
  CHECK(h.distance == 0.5);
  CHECK(h.normal == Vector3d(0, 0, 1));
  h = s.closest(0, {0.2, 0.3, -0.5});  // below: the normal points down, to the centre
  CHECK(h.normal == Vector3d(0, 0, -1));
  h = s.closest(0, {0.5, -0.3, 0.4});  // beyond the edge y = 0
  CHECK(h.feature == MeshFeature::edge);
  CHECK(h.distance == Approx(0.5).epsilon(1e-14));
  CHECK((h.point - Vector3d(0.5, 0, 0)).norm() < 1e-15);
  h = s.closest(0, {1.3, -0.4, 0});  // beyond the corner (1, 0, 0)
  CHECK(h.feature == MeshFeature::vertex);
  CHECK(h.point == Vector3d(1, 0, 0));
  CHECK(h.distance == Approx(0.5).epsilon(1e-14));
  h = s.closest(0, {0.6, 0.6, 0.1});  // beyond the hypotenuse
  CHECK(h.feature == MeshFeature::edge);
  CHECK(h.distance == Approx(std::sqrt(0.02 + 0.01)).epsilon(1e-14));
}

TEST_CASE("mesh surface: one contact on a flat patch, at a shared edge and a shared vertex",
          "[mesh]") {
  MeshSurface s(test::flat_grid(1.0, 4));  // vertices every 0.5, diagonals along x = y
  s.build_grid(0.2);
  const double r = 0.1;
  MeshHit hits[MeshSurface::max_hits];
  // Over a face, on a diagonal (edge of two triangles), on a grid line, on a
  // vertex shared by six triangles, and beside each: one contact, straight down.
  for (Vector3d x : {Vector3d(0.1, 0.3, 0.09), Vector3d(0.2, 0.2, 0.09), Vector3d(0.2, 0.0, 0.09),
                     Vector3d(0.0, 0.0, 0.09), Vector3d(0.5, 0.5, 0.09),
                     Vector3d(1e-13, -1e-13, 0.09), Vector3d(0.25 + 1e-15, 0.25, 0.09)}) {
    INFO(x.transpose());
    const int n = s.contacts(x, r, r, hits);
    REQUIRE(n == 1);
    CHECK(hits[0].distance == Approx(0.09).epsilon(1e-14));
    // (at a vertex or edge the normal points from it to the centre: off the
    // vertical by the centre's offset / distance)
    CHECK((hits[0].normal - Vector3d(0, 0, 1)).norm() < 1e-11);
  }
  // Out of reach: none.
  CHECK(s.contacts(Vector3d(0.1, 0.1, 0.2), r, r, hits) == 0);
}

TEST_CASE("mesh surface: a convex edge gives one contact whose normal turns continuously",
          "[mesh]") {
  const double slope = 0.5;
  MeshSurface s(test::roof(1.0, slope));
  s.build_grid(0.2);
  const double r = 0.1;
  MeshHit hits[MeshSurface::max_hits];
  // A sphere carried across the ridge at constant height above it: the
  // contact is on the left face, then on the ridge (normal from the ridge to
  // the centre), then on the right face; one at every position, its normal
  // changing by no more than the step allows.
  // At this height the ridge is nearest for |x| < h slope, a face beyond.
  Vector3d last_normal(0, 0, 0);
  const double h = 0.07;
  for (int k = -300; k <= 300; ++k) {
    const Vector3d x(k * 2e-4, 0.1, h);
    const int n = s.contacts(x, r, r, hits);
    REQUIRE(n == 1);
    if (!last_normal.isZero()) CHECK((hits[0].normal - last_normal).norm() < 0.02);
    last_normal = hits[0].normal;
    // The distance to the roof, by hand: to a face's plane where the foot of
    // the perpendicular lies on that face, else to the ridge.
    const Vector3d up_right = Vector3d(slope, 0, 1).normalized();
    const Vector3d up_left = Vector3d(-slope, 0, 1).normalized();
    const Vector3d rel(x.x(), 0, x.z());
    const double d_right = rel.dot(up_right), d_left = rel.dot(up_left);
    double expect = rel.norm();
    if ((rel - d_right * up_right).x() >= 0) expect = d_right;
    if ((rel - d_left * up_left).x() <= 0) expect = d_left;
    CHECK(hits[0].distance == Approx(expect).epsilon(1e-12));
  }
}

TEST_CASE("mesh surface: a concave edge gives one contact per face", "[mesh]") {
  MeshSurface s(test::corner(1.0));
  s.build_grid(0.2);
  const double r = 0.1;
  MeshHit hits[MeshSurface::max_hits];
  // In the corner, pressed into both faces.
  int n = s.contacts(Vector3d(0.09, 0.2, 0.08), r, r, hits);
  REQUIRE(n == 2);
  CHECK(hits[0].distance == Approx(0.08));
  CHECK((hits[0].normal - Vector3d(0, 0, 1)).norm() < 1e-15);
  CHECK(hits[1].distance == Approx(0.09));
  CHECK((hits[1].normal - Vector3d(1, 0, 0)).norm() < 1e-15);
  // Touching the floor only (the side is out of reach); the floor's other
  // triangle finds its edge with this one, which is nearer: one contact.
  n = s.contacts(Vector3d(0.15, 0.2, 0.08), r, r, hits);
  REQUIRE(n == 1);
  CHECK(hits[0].normal == Vector3d(0, 0, 1));
}

TEST_CASE("mesh surface: the grid examines a few triangles of a 10^5-triangle mesh", "[mesh]") {
  const int cells = 224;  // 2 * 224^2 = 100352 triangles
  MeshSurface s(test::flat_grid(1.0, cells));
  REQUIRE(s.triangle_count() == 100352);
  const double r = 2.0 / cells;  // spheres as large as a grid square
  s.build_grid(1.5 * r);
  MeshHit hits[MeshSurface::max_hits];
  std::int64_t tested = 0;
  int queries = 0;
  for (int k = 0; k < 200; ++k) {
    const Vector3d x(-0.9 + 0.009 * k, 0.3 - 0.004 * k, 0.9 * r);
    REQUIRE(s.contacts(x, r, r, hits, &tested) == 1);
    CHECK(hits[0].distance == Approx(0.9 * r).epsilon(1e-12));
    ++queries;
  }
  const double per_query = static_cast<double>(tested) / queries;
  INFO("triangles examined per sphere: " << per_query);
  // A cell 3 r wide holds about 2 (3 r / (2/224))^2 = 18 triangles (listed
  // in the cells they come near), and a sphere overlaps up to 4 cells.
  CHECK(per_query < 400);
  CHECK(per_query > 2);
}

TEST_CASE("mesh surface: edge contacts are not merged, however alike their normals", "[mesh]") {
  // A plate z = 0 with a square hole of side 2a = 0.3 r, and a sphere sunk into
  // it: it rests on the four edges' midpoints, whose normals are tilted by
  // atan(a / h) = 8.6 degrees from z, so any two lie less than flat_angle (20
  // degrees) apart. They are four contacts at the closed form's depth, and
  // their normals sum to a vertical push.
  const double r = 0.1, a = 0.015;
  const double h = std::sqrt(r * r - a * a) - 1e-4;  // 1e-4 of overlap on each edge, about
  Triangles m;
  m.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0},
                {-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}};
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t o0 = k, o1 = (k + 1) % 4, i0 = 4 + k, i1 = 4 + (k + 1) % 4;
    m.triangles.push_back({o0, o1, i1});
    m.triangles.push_back({o0, i1, i0});
  }
  MeshSurface s(m);
  s.build_grid(0.2);
  const Vector3d x(0, 0, h);
  MeshHit hits[MeshSurface::max_hits];
  REQUIRE(s.contacts(x, r, r, hits) == 4);
  Vector3d sum = Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    CHECK(hits[k].feature == MeshFeature::edge);
    CHECK(hits[k].distance == Approx(std::sqrt(a * a + h * h)).epsilon(1e-12));
    sum += hits[k].normal;
  }
  CHECK(std::abs(sum.x()) < 1e-12);
  CHECK(std::abs(sum.y()) < 1e-12);
  CHECK(sum.z() == Approx(4 * h / std::sqrt(a * a + h * h)).epsilon(1e-12));
}

TEST_CASE("mesh surface: a shallow concave fold gives one contact, the nearer, a steep one two",
          "[mesh]") {
  // Two faces meeting along the y axis, each tilted up by `tilt` from the floor z = 0
  // (a V of 180 - 2 tilt degrees), and a sphere pressed into the fold, a little to the
  // right: its normals to the two faces differ by 2 tilt.
  auto fold = [](double tilt_degrees) {
    const double t = tilt_degrees * M_PI / 180, w = 1.0;
    Triangles m;
    m.vertices = {{-w * std::cos(t), -1, w * std::sin(t)},
                  {-w * std::cos(t), 1, w * std::sin(t)},
                  {0, -1, 0},
                  {0, 1, 0},
                  {w * std::cos(t), -1, w * std::sin(t)},
                  {w * std::cos(t), 1, w * std::sin(t)}};
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {2, 4, 5}, {2, 5, 3}};
    return MeshSurface(m);
  };
  const double r = 0.1;
  const Vector3d x(0.001, 0.2, 0.09);
  MeshHit hits[MeshSurface::max_hits];
  for (const double tilt : {2.0, 5.0, 9.9}) {  // folds of 4, 10 and 19.8 degrees: below 20
    MeshSurface s = fold(tilt);
    s.build_grid(0.2);
    INFO("tilt " << tilt);
    REQUIRE(s.contacts(x, r, r, hits) == 1);
    // The nearer face is the right one (the centre sits right of the fold).
    const double t = tilt * M_PI / 180;
    const Vector3d right_normal(-std::sin(t), 0, std::cos(t));
    CHECK((hits[0].normal - right_normal).norm() < 1e-12);
    CHECK(hits[0].distance == Approx(x.dot(right_normal)).epsilon(1e-12));
    // With merging off, both faces hold a contact.
    s.set_flat_angle(0);
    CHECK(s.contacts(x, r, r, hits) == 2);
  }
  for (const double tilt : {10.1, 30.0}) {  // folds of 20.2 and 60 degrees: two contacts
    MeshSurface s = fold(tilt);
    s.build_grid(0.2);
    INFO("tilt " << tilt);
    CHECK(s.contacts(x, r, r, hits) == 2);
  }
  MeshSurface s = fold(5);
  CHECK_THROWS_WITH(s.set_flat_angle(90), Catch::Contains("flat_angle must be in [0, 90)"));
  CHECK_THROWS_WITH(s.set_flat_angle(-1), Catch::Contains("flat_angle"));
}

TEST_CASE("mesh surface: an unjoined seam, a T-junction and a crack give the plane's one contact",
          "[mesh]") {
  // A floor z = 0, [-1, 1] x [-1, 1], cut along x = 0 into a left and a right
  // half whose corners on the cut are not shared: moved apart by `gap` (a
  // crack), or the right half's edge split at y = 0.3 (a T-junction). A sphere
  // anywhere near the cut rests on one contact at the plane's depth, as on the
  // joined floor; a sphere over a crack wider than the contact can feel holds
  // two.
  auto floor = [](double gap, bool t_junction) {
    Triangles m;
    m.vertices = {{-1, -1, 0}, {-gap, -1, 0}, {-gap, 1, 0}, {-1, 1, 0},
                  {0, -1, 0},  {1, -1, 0},    {1, 1, 0},    {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    if (t_junction) {
      m.vertices.push_back({0, 0.3, 0});  // 8: on the left half's long edge
      m.triangles.insert(m.triangles.end(), {{4, 5, 8}, {5, 6, 8}, {8, 6, 7}});
    } else {
      m.triangles.insert(m.triangles.end(), {{4, 5, 6}, {4, 6, 7}});
    }
    MeshSurface s(m);
    s.build_grid(0.2);
    return s;
  };
  const double r = 0.1, depth = 1e-4;
  MeshHit hits[MeshSurface::max_hits];
  for (const double gap : {0.0, 1e-12, 1e-9, 0.5e-3 * r}) {
    for (const bool t_junction : {false, true}) {
      if (t_junction && gap > 0) continue;
      const MeshSurface s = floor(gap, t_junction);
      // Across the cut, over the T's corner and beside it.
      for (const double x : {-0.02, -0.004, -gap / 2, 0.0, 0.004, 0.02})
        for (const double y : {-0.5, 0.3, 0.301, 0.7}) {
          INFO("gap " << gap << " T " << t_junction << " at " << x << ", " << y);
          REQUIRE(s.contacts(Vector3d(x, y, r - depth), r, r, hits) == 1);
          // Over the crack itself the sphere dips into it: gap^2 / (8 r) deeper at most.
          CHECK(hits[0].distance == Approx(r - depth).epsilon(1e-7));
        }
    }
  }
  // A crack of a tenth of the radius is a real gap: a sphere sunk into it rests on both lips.
  const double half = 0.05 * r;
  const MeshSurface wide = floor(2 * half, false);
  REQUIRE(wide.contacts(Vector3d(-half, 0, std::sqrt(r * r - half * half) - depth), r, r, hits) ==
          2);
  for (int k = 0; k < 2; ++k) CHECK(hits[k].feature == MeshFeature::edge);
}

TEST_CASE("mesh surface: a far stray vertex does not hide the rest of the mesh", "[mesh]") {
  // A 2 cm floor at the origin and one triangle 10^28 m away, in single
  // precision as an STL file holds them: the grid's cells grow to ~10^21 m,
  // and the floor, in the corner of the first, must stay listed there.
  const double L = static_cast<float>(0.01), far = static_cast<float>(1e28);
  Triangles m;
  m.vertices = {{-L, -L, 0}, {L, -L, 0},  {L, L, 0},  {-L, L, 0},
                {far, 0, 0}, {far, 1, 0}, {far, 0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  MeshSurface s(m);
  s.build_grid(1e-3);
  MeshHit hits[MeshSurface::max_hits];
  REQUIRE(s.contacts(Vector3d(0.001, 0.0013, 0.9e-3), 1e-3, 1e-3, hits) == 1);
  CHECK(hits[0].distance == Approx(0.9e-3).epsilon(1e-12));
}

TEST_CASE("mesh surface: a sphere over a hole's corner keeps both rims' contacts", "[mesh]") {
  // A plate z = 0 with a square hole [0, H]^2 (its corner V at the origin) and a
  // sphere sunk into the hole beside the rim x = 0, a little past V: it rests on
  // the rims y = 0 and x = 0, whose triangles meet only at V. However close the
  // centre comes to the corner's plane x = 0 (a from 0.5e-3 r to 2e-3 r), both
  // contacts stay: the seam tolerance must not join a corner's two rims.
  const double r = 1.0, H = 1.6 * r, L = 5 * r;
  Triangles m;
  m.vertices = {{-L, -L, 0}, {L, -L, 0}, {L, L, 0}, {-L, L, 0},
                {0, 0, 0},   {H, 0, 0},  {H, H, 0}, {0, H, 0}};
  m.triangles = {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                 {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  MeshSurface s(m);
  s.build_grid(1.5 * r);
  MeshHit hits[MeshSurface::max_hits];
  for (const double a : {0.5e-3 * r, 0.99e-3 * r, 1.01e-3 * r, 2e-3 * r}) {
    INFO("centre " << a / r << " r from the corner's plane");
    const int n = s.contacts(Vector3d(a, 0.5 * r, 0.8 * r), r, r, hits);
    REQUIRE(n == 2);
    // One on each rim: the nearer is the rim x = 0 (a away), the other y = 0.
    CHECK(hits[0].point.x() == Approx(0).margin(1e-15));
    CHECK(hits[1].point.y() == Approx(0).margin(1e-15));
  }
}
