// Polyline walls (2D): closest points against hand values; a disk meets a
// one-segment floor exactly as the analytic plane, rolls across a joint with
// one contact and the plane's force, meets a circle of arcs as the analytic
// cylinder (at rest and turning), rests in a concave V on two contacts that
// carry its weight, is dragged by a moving polyline, and bad input is refused
// naming the parameter.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "engine/simulation.hpp"
#include "geometry/polyline_surface.hpp"

using namespace granule;
using Eigen::Vector2d;

namespace {
bool near_equal(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + 1e-300;
}

std::unique_ptr<Simulation<2>> scene(const std::string& model = "hertz_mindlin") {
  auto sim = std::make_unique<Simulation<2>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", 2500, 5e7, 0.3, 0});
  sim->add_material({"w", 0, 5e7, 0.3, 0});
  ParamValues law = {{"restitution", 0.6}, {"friction", 0.35}};
  if (model == "linear") law = {{"k_normal", 2000}, {"restitution", 0.7}, {"friction", 0.4}};
  sim->set_contact("p", "p", model, law);
  sim->set_contact("p", "w", model, law);
  sim->set_steps_per_contact(60);
  sim->set_record_contacts(true);
  return sim;
}
PolylineWallSpec polyline(std::vector<std::array<double, 2>> points, bool closed = false,
                          std::vector<PolylineWallSpec::Arc> arcs = {}) {
  PolylineWallSpec s;
  s.name = "line";
  s.material = 1;
  s.points = std::move(points);
  s.closed = closed;
  s.arcs = std::move(arcs);
  return s;
}
void add_plane(Simulation<2>& sim, Triple normal, Triple velocity = {0, 0, 0}) {
  WallSpec w;
  w.name = "plane";
  w.material = 1;
  w.normal = normal;
  w.velocity = velocity;
  sim.add_wall(w);
}
void add_cylinder(Simulation<2>& sim, double R, double omega = 0) {
  WallSpec w;
  w.name = "cylinder";
  w.type = WallType::cylinder;
  w.material = 1;
  w.radius = R;
  w.inside = true;
  w.angular_velocity = omega;
  sim.add_wall(w);
}
ParticleSpec disk(Triple x, Triple v = {0, 0, 0}, double r = 1e-3) {
  ParticleSpec p;
  p.position = x, p.velocity = v, p.radius = r, p.material = 0;
  return p;
}
// A circle of radius R about the origin as four quarter arcs, counter-
// clockwise, bulging outwards (to the right of each segment).
PolylineWallSpec circle_of_arcs(double R) {
  PolylineWallSpec s = polyline({{R, 0}, {0, R}, {-R, 0}, {0, -R}}, true);
  for (int k = 1; k <= 4; ++k) s.arcs.push_back({k, -R});
  return s;
}

struct Step {
  int contacts = 0;
  double overlap = 0, normal_force = 0, tangential_x = 0, tangential_y = 0;
};
std::vector<Step> run(Simulation<2>& sim, std::int64_t steps) {
  std::vector<Step> out;
  for (std::int64_t k = 0; k < steps; ++k) {
    sim.advance(1);
    const auto c = sim.contacts();
    Step s;
    s.contacts = static_cast<int>(c.size());
    for (const auto& x : c) {
      s.overlap += x.overlap;
      s.normal_force += x.normal_force;
      s.tangential_x += x.tangential_force[0];
      s.tangential_y += x.tangential_force[1];
    }
    out.push_back(s);
  }
  return out;
}
// Whether two runs agree step by step to `rel` (forces relative to `scale`).
bool same_runs(const std::vector<Step>& a, const std::vector<Step>& b, double rel, double scale) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].contacts != b[k].contacts) return false;
    if (!near_equal(a[k].overlap, b[k].overlap, rel)) return false;
    if (std::abs(a[k].normal_force - b[k].normal_force) > rel * scale) return false;
    if (std::abs(a[k].tangential_x - b[k].tangential_x) > rel * scale) return false;
    if (std::abs(a[k].tangential_y - b[k].tangential_y) > rel * scale) return false;
  }
  return true;
}
}  // namespace

TEST_CASE("polyline surface: closest points on a line, an arc and a joint", "[polyline]") {
  Polyline line;
  line.points = {{0, 0}, {2, 0}, {2, 2}};
  line.radius = {0, 1};  // the second segment: a half circle about (2, 1), bulging left (-x)
  PolylineSurface s(line);
  PolylineHit h = s.closest(0, {0.5, 0.25});
  CHECK(h.feature == MeshFeature::face);
  CHECK(h.distance == 0.25);
  CHECK(h.normal == Vector2d(0, 1));
  h = s.closest(0, {0.5, -0.25});  // the other side
  CHECK(h.normal == Vector2d(0, -1));
  h = s.closest(0, {-0.3, 0.4});  // beyond the first point
  CHECK(h.feature == MeshFeature::vertex);
  CHECK(h.element == 0);
  CHECK(h.distance == Approx(0.5).epsilon(1e-15));
  CHECK(s.arc_center(1) == Vector2d(2, 1));
  h = s.closest(1, {0.5, 1});  // outside the half circle, on its middle ray
  CHECK(h.feature == MeshFeature::face);
  CHECK(h.distance == 0.5);
  CHECK(h.curvature_radius == 1);
  CHECK(!h.concave);
  CHECK(h.normal == Vector2d(-1, 0));
  h = s.closest(1, {1.75, 1});  // inside it
  CHECK(h.concave);
  CHECK(h.distance == 0.75);
  CHECK(h.normal == Vector2d(1, 0));
  h = s.closest(1, {3, 1});  // the side the arc does not reach: its ends are nearest
  CHECK(h.feature == MeshFeature::vertex);
  CHECK(h.distance == Approx(std::sqrt(2.0)).epsilon(1e-15));
  // The outline for drawing: the line's two points, then the half circle in
  // 36 pieces of 5 degrees, every point on it, bulging to -x.
  const auto outline = s.outline(5);
  REQUIRE(outline.size() == 2 + 36);
  CHECK(outline[0] == Vector2d(0, 0));
  CHECK(outline.back() == Vector2d(2, 2));
  for (std::size_t k = 2; k < outline.size(); ++k) {
    CHECK((outline[k] - Vector2d(2, 1)).norm() == Approx(1).epsilon(1e-14));
    CHECK(outline[k].x() <= 2 + 1e-15);
  }
  CHECK(s.reach_from({2, 1}) == Approx(std::sqrt(5.0)));
}

TEST_CASE("polyline surface: one contact on a straight or convex chain, two in a concave corner",
          "[polyline]") {
  const double r = 0.1;
  Polyline flat;
  flat.points = {{-1, 0}, {0, 0}, {1, 0}};
  PolylineSurface f(flat);
  PolylineHit hit[PolylineSurface::max_hits];
  for (double x : {-0.3, -1e-17, 0.0, 1e-17, 0.2}) {
    INFO("x = " << x);
    REQUIRE(f.contacts({x, 0.09}, r, 0.12, hit) == 1);
    CHECK(hit[0].distance == Approx(0.09).epsilon(1e-15));
    CHECK((hit[0].normal - Vector2d(0, 1)).norm() < 1e-15);
  }
  // A convex corner (a roof): one contact, at the joint, its normal turning
  // from one side's to the other's.
  Polyline roof;
  roof.points = {{-1, -1}, {0, 0}, {1, -1}};
  PolylineSurface c(roof);
  double last_angle = -1;
  for (int k = -10; k <= 10; ++k) {
    const double x = 0.01 * k;
    REQUIRE(c.contacts({x, 0.05}, r, 0.2, hit) == 1);
    const double angle = std::atan2(hit[0].normal.x(), hit[0].normal.y());
    CHECK(angle >= last_angle - 1e-15);
    last_angle = angle;
    if (std::abs(x) < 0.045) CHECK(hit[0].feature == MeshFeature::vertex);
    if (std::abs(x) < 0.045) CHECK(hit[0].distance == Approx(std::hypot(x, 0.05)).epsilon(1e-15));
  }
  CHECK(last_angle == Approx(M_PI / 4));
  // A concave corner (a V): one contact per side.
  Polyline vee;
  vee.points = {{-1, 1}, {0, 0}, {1, 1}};
  PolylineSurface v(vee);
  REQUIRE(v.contacts({0.01, 0.14}, r, 0.12, hit) == 2);
  CHECK(hit[0].feature == MeshFeature::face);
  CHECK(hit[1].feature == MeshFeature::face);
  CHECK(hit[0].triangle != hit[1].triangle);
}

TEST_CASE("polyline surface: what a closed chain encloses, arcs bulging out and in", "[polyline]") {
  // A unit square whose bottom side bulges out (down) and whose top side
  // bulges in (down too), both half circles of radius 1/2.
  Polyline sq;
  sq.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  sq.radius = {-0.5, 0, 0.5, 0};  // counter-clockwise: right of the bottom is down
  sq.closed = true;
  PolylineSurface s(sq);
  CHECK(s.encloses({0.5, 0.05}));
  CHECK(s.encloses({0.5, -0.4}));   // in the bottom's outward bulge
  CHECK(!s.encloses({0.5, -0.6}));  // below it
  CHECK(!s.encloses({0.5, 0.6}));   // in the top's inward bulge: outside
  CHECK(s.encloses({0.02, 0.5}));   // beside that bulge, still inside
  CHECK(!s.encloses({1.2, 0.5}));
  CHECK(!s.encloses({-0.2, 0.0}));
  Polyline open = sq;
  open.closed = false;
  open.radius = {-0.5, 0, 0.5};
  CHECK(!PolylineSurface(open).encloses({0.5, 0.05}));
}

TEST_CASE(
    "polyline walls: fill places no particle inside a solid polyline, and does inside a "
    "closed one",
    "[polyline]") {
  for (bool solid : {true, false}) {
    auto sim = scene();
    PolylineWallSpec ring = circle_of_arcs(0.004);
    ring.solid = solid;
    sim->add_polyline_wall(ring);
    FillSpec f;
    f.shape = RegionShape::ball;
    f.radius = 0.01;
    f.count = 200;
    f.radius_min = f.radius_max = 2e-4;
    f.material = 0;
    const auto ids = sim->fill(f);
    int inside = 0;
    for (auto id : ids) {
      const Triple x = sim->position(id);
      const double rho = std::hypot(x[0], x[1]);
      CHECK(std::abs(rho - 0.004) >= 2e-4);  // never on the line
      inside += rho < 0.004;
    }
    INFO("solid " << solid << ": " << inside << " of 200 inside");
    if (solid) CHECK(inside == 0);
    if (!solid) CHECK(inside > 10);  // about (4/10)^2 of them
  }
}

TEST_CASE("polyline walls: a disk on a one-segment floor is the disk on the plane", "[polyline]") {
  for (const std::string model : {"linear", "hertz_mindlin"}) {
    INFO(model);
    auto drop = [&](bool line) {
      auto sim = scene(model);
      sim->set_gravity({0, -9.81, 0});
      if (line)
        sim->add_polyline_wall(polyline({{-0.02, 0}, {0.02, 0}}));
      else
        add_plane(*sim, {0, 1, 0});
      sim->add_particle(disk({0.001, 1.2e-3, 0}, {0.1, -0.2, 0}));
      sim->prepare();
      auto steps = run(*sim, static_cast<std::int64_t>(0.05 / sim->time_step()));
      return std::tuple{steps, sim->position(0), sim->wall_force(0)};
    };
    const auto [plane, plane_end, plane_force] = drop(false);
    const auto [line, line_end, line_force] = drop(true);
    int touching = 0;
    double peak = 0;
    for (const Step& s : plane) touching += s.contacts, peak = std::max(peak, s.normal_force);
    REQUIRE(touching > 100);  // it lands and rests
    CHECK(same_runs(line, plane, 1e-12, peak));
    CHECK(near_equal(line_end[0], plane_end[0], 1e-12));
    CHECK(near_equal(line_end[1], plane_end[1], 1e-12));
    CHECK(near_equal(line_force[1], plane_force[1], 1e-12));
  }
}

TEST_CASE("polyline walls: rolling across the joint of a straight floor, one contact, no jump",
          "[polyline]") {
  const double r = 1e-3, v = 0.05;
  auto roll = [&](bool line) {
    auto sim = scene("linear");
    sim->set_gravity({0, -9.81, 0});
    if (line)
      sim->add_polyline_wall(polyline({{-0.02, 0}, {0, 0}, {0.02, 0}}));
    else
      add_plane(*sim, {0, 1, 0});
    ParticleSpec p = disk({-0.004, r, 0}, {v, 0, 0});
    p.spin = {0, 0, -0.5 * v / r};  // sliding and rolling at once
    sim->add_particle(p);
    sim->set_position(0, {-0.004, r - sim->mass(0) * 9.81 / 2000, 0});  // resting overlap
    sim->prepare();
    auto steps = run(*sim, static_cast<std::int64_t>(0.15 / sim->time_step()));
    return std::tuple{steps, sim->position(0)};
  };
  const auto [plane, plane_end] = roll(false);
  const auto [line, line_end] = roll(true);
  REQUIRE(line_end[0] > 0.002);  // it crossed the joint at x = 0
  bool one_each_step = true;
  double largest_jump = 0, weight = 0;
  for (std::size_t k = 0; k < line.size(); ++k) {
    one_each_step = one_each_step && line[k].contacts == 1;
    if (k)
      largest_jump =
          std::max(largest_jump, std::abs(line[k].normal_force - line[k - 1].normal_force));
    weight = std::max(weight, plane[k].normal_force);
  }
  CHECK(one_each_step);
  CHECK(same_runs(line, plane, 1e-12, weight));
  INFO("largest step-to-step change of the normal force " << largest_jump);
  CHECK(largest_jump < 1e-3 * weight);
  CHECK(near_equal(line_end[0], plane_end[0], 1e-12));
}

TEST_CASE("polyline walls: a circle of arcs is the analytic cylinder", "[polyline]") {
  // Dyadic numbers and a 3-4-5 triangle, so both walls' overlaps are exact:
  // the disk's centre at distance 5 t from the axis, overlapping the circle
  // of radius 5 t + r - delta by delta.
  const double t = 0.0078125, r = 0.0009765625, delta = 0.000003814697265625;
  const double R = 5 * t + r - delta;
  auto at_rest = [&](bool arcs) {
    auto sim = scene();
    if (arcs)
      sim->add_polyline_wall(circle_of_arcs(R));
    else
      add_cylinder(*sim, R);
    sim->add_particle(disk({3 * t, -4 * t, 0}, {0, 0, 0}, r));
    sim->prepare();
    sim->advance(1);
    const auto c = sim->contacts();
    REQUIRE(c.size() == 1);
    return c[0];
  };
  const ContactRecord cyl = at_rest(false), arc = at_rest(true);
  CHECK(cyl.overlap == delta);
  CHECK(arc.overlap == delta);
  CHECK(near_equal(arc.normal_force, cyl.normal_force, 1e-12));
  CHECK(near_equal(arc.normal[0], cyl.normal[0], 1e-12));
  CHECK(near_equal(arc.normal[1], cyl.normal[1], 1e-12));

  // Swinging across the joints at the bottom of the circle (gravity along
  // +x: the bottom is the joint at (R, 0)), with the chamber still and
  // turning (its surface drags the disk): one contact every step, the
  // cylinder's forces, and the same torque on the wall.
  for (double omega : {0.0, 3.0}) {
    INFO("omega " << omega);
    auto swing = [&](bool arcs) {
      auto sim = scene();
      sim->set_gravity({9.81, 0, 0});
      PolylineWallSpec c = circle_of_arcs(0.02);
      c.angular_velocity = omega;
      if (arcs)
        sim->add_polyline_wall(c);
      else
        add_cylinder(*sim, 0.02, omega);
      const double a = -0.3, rho = 0.02 - 1e-3 + 1e-7;
      sim->add_particle(disk({rho * std::cos(a), rho * std::sin(a), 0}, {0, 0, 0}, 1e-3));
      sim->prepare();
      auto steps = run(*sim, static_cast<std::int64_t>(0.2 / sim->time_step()));
      return std::tuple{steps, sim->position(0), sim->wall_axial_torque(0)};
    };
    const auto [cyl_steps, cyl_end, cyl_torque] = swing(false);
    const auto [arc_steps, arc_end, arc_torque] = swing(true);
    double weight = 0;
    for (const Step& s : cyl_steps) weight = std::max(weight, s.normal_force);
    bool at_most_one = true;
    std::size_t touching = 0;
    for (const Step& s : arc_steps)
      at_most_one = at_most_one && s.contacts <= 1, touching += s.contacts;
    CHECK(at_most_one);
    CHECK(touching > 0.9 * arc_steps.size());
    CHECK(same_runs(arc_steps, cyl_steps, 1e-9, weight));
    CHECK(std::abs(arc_end[0] - cyl_end[0]) < 1e-9 * 0.02);
    CHECK(std::abs(arc_end[1] - cyl_end[1]) < 1e-9 * 0.02);
    CHECK(std::abs(arc_torque - cyl_torque) <= 1e-9 * weight * 0.02);
    if (omega != 0) CHECK(std::abs(cyl_torque) > 0);
  }
}

TEST_CASE("polyline walls: a disk in a concave V rests on two contacts that carry its weight",
          "[polyline]") {
  auto sim = scene();
  const double g = 9.81, r = 1e-3;
  sim->set_gravity({0, -g, 0});
  sim->add_polyline_wall(polyline({{-0.01, 0.01}, {0, 0}, {0.01, 0.01}}));
  sim->add_particle(disk({0, r * std::sqrt(2.0) + 1e-5, 0}, {0, 0, 0}, r));
  sim->prepare();
  sim->advance(static_cast<std::int64_t>(0.3 / sim->time_step()));
  const auto c = sim->contacts();
  REQUIRE(c.size() == 2);
  const double m = sim->mass(0);
  CHECK(c[0].normal_force > 0.3 * m * g);
  CHECK(near_equal(c[0].normal_force, c[1].normal_force, 1e-6));  // the V is symmetric
  CHECK(c[0].normal[0] * c[1].normal[0] < 0);                     // one on each side
  const Triple f = sim->wall_force(0);
  CHECK(f[0] == Approx(0).margin(1e-6 * m * g));
  CHECK(f[1] == Approx(-m * g).epsilon(1e-4));  // at rest: the V carries the weight
  CHECK(std::abs(sim->velocity(0)[1]) < 1e-4);
}

TEST_CASE("polyline walls: a translating polyline drags a disk as a moving plane does",
          "[polyline]") {
  const double u = 0.02;
  auto drag = [&](bool line) {
    auto sim = scene("linear");
    sim->set_gravity({0, -9.81, 0});
    if (line) {
      PolylineWallSpec s = polyline({{-0.02, 0}, {0.02, 0}});
      s.velocity = {u, 0, 0};
      sim->add_polyline_wall(s);
    } else {
      add_plane(*sim, {0, 1, 0}, {u, 0, 0});
    }
    sim->add_particle(disk({0, 1e-3, 0}));
    sim->set_position(0, {0, 1e-3 - sim->mass(0) * 9.81 / 2000, 0});
    sim->prepare();
    auto steps = run(*sim, static_cast<std::int64_t>(0.1 / sim->time_step()));
    return std::tuple{steps, sim->velocity(0), sim->spin(0), sim->wall(0).point};
  };
  const auto [plane, pv, pw, pp] = drag(false);
  const auto [line, lv, lw, lp] = drag(true);
  REQUIRE(line.front().contacts == 1);
  CHECK(line.front().tangential_x > 0);  // the surface velocity pulls it along +x
  double weight = 0;
  for (const Step& s : plane) weight = std::max(weight, s.normal_force);
  CHECK(same_runs(line, plane, 1e-12, weight));
  // At the end it rolls on the floor: its contact point moves with the surface.
  const double contact_point_vx = lv[0] + lw[2] * 1e-3;
  CHECK(contact_point_vx == Approx(u).epsilon(0.02));
  CHECK(lp[0] == Approx(u * 0.1).epsilon(1e-3));  // the polyline moved
}

TEST_CASE("polyline walls: a blade moving at a disk at rest meets it whichever way it moves",
          "[polyline]") {
  // No gravity, the disk at rest 9 mm from the blade: it finds the disk only
  // through its own travel, so the lists must see the blade move, along -x as
  // along +x (a signed step cancelled the travel counted for a -x velocity).
  const double speed = 0.5;
  for (int axis = 0; axis < 2; ++axis)
    for (const double sign : {1.0, -1.0}) {
      auto sim = scene("linear");
      const double start = -sign * 0.01;  // the blade starts on the side it moves away from
      PolylineWallSpec s = axis == 0 ? polyline({{start, -0.005}, {start, 0.005}})
                                     : polyline({{-0.005, start}, {0.005, start}});
      s.velocity = {axis == 0 ? sign * speed : 0, axis == 1 ? sign * speed : 0, 0};
      sim->add_polyline_wall(s);
      sim->add_particle(disk({0, 0, 0}));
      sim->prepare();
      run(*sim, static_cast<std::int64_t>(0.03 / sim->time_step()));
      INFO("axis " << axis << ", moving " << sign);
      // Struck by an immovable wall at `speed`: (1 + e) times it, e = 0.7 (to 2 %, n = 60).
      CHECK(sim->velocity(0)[axis] == Approx(sign * 1.7 * speed).epsilon(0.02));
    }
}

TEST_CASE("polyline walls: a blade that would step over a disk stops the run, one far off does not",
          "[polyline]") {
  auto run = [](Triple velocity, double distance, double omega = 0) {
    auto sim = scene("linear");
    sim->set_time_step(1e-5);
    PolylineWallSpec s = polyline({{-0.01, -distance}, {0.01, -distance}});
    s.velocity = velocity;
    s.angular_velocity = omega;
    sim->add_polyline_wall(s);
    sim->add_particle(disk({0.005, 0, 0}));
    sim->advance(3);
  };
  // 260 m/s: 2.6 mm a step, 2.6 radii (the blade crossed the disk unseen).
  CHECK_THROWS_WITH(run({0, 260, 0}, 1.5e-3),
                    Catch::Contains("wall 'line' moves") &&
                        Catch::Contains("more than the smallest free particle's radius"));
  CHECK_THROWS_WITH(run({0, -260, 0}, -1.5e-3), Catch::Contains("wall 'line' moves"));
  CHECK_NOTHROW(run({0, 260, 0}, 1.0));      // a metre off
  CHECK_NOTHROW(run({0, -260, 0}, 1.5e-3));  // pulled away
  CHECK_NOTHROW(run({260, 0, 0}, 1.5e-3));   // sliding along itself
  // Turning about the origin at 3e4 rad/s: the blade's point under the disk, 5 mm
  // from the axis, rises 1.5 mm a step.
  CHECK_THROWS_WITH(run({0, 0, 0}, 1.5e-3, 3e4), Catch::Contains("wall 'line' moves"));
  CHECK_NOTHROW(run({0, 0, 0}, 1.5e-3, -3e4));  // turning away
  CHECK_NOTHROW(run({0, 0, 0}, 1.5e-3, 1));
  // An L sliding along its floor, on which the disk rests: the floor's nearest point
  // slides along itself, the blade 0.5 mm off closes 2.6 mm a step.
  auto ell = [](double speed) {
    auto sim = scene("linear");
    sim->set_time_step(1e-5);
    PolylineWallSpec s = polyline({{-0.01, 0}, {0.0065, 0}, {0.0065, 0.005}});
    s.velocity = {-speed, 0, 0};
    sim->add_polyline_wall(s);
    sim->add_particle(disk({0.005, 1e-3, 0}));
    sim->advance(3);
  };
  CHECK_THROWS_WITH(ell(260), Catch::Contains("wall 'line' moves"));
  CHECK_NOTHROW(ell(0.1));
}

TEST_CASE("polyline walls: the same run across a checkpoint", "[polyline]") {
  auto make = [] {
    auto sim = scene();
    sim->set_gravity({0, -9.81, 0});
    PolylineWallSpec c = circle_of_arcs(0.01);
    c.angular_velocity = 5, c.velocity = {0.001, 0, 0};
    sim->add_polyline_wall(c);
    for (int k = 0; k < 5; ++k)
      sim->add_particle(disk({-0.004 + 0.0021 * k, -0.007, 0}, {0, 0, 0}, 0.9e-3));
    sim->prepare();
    return sim;
  };
  auto one = make(), restarted = make();
  std::int64_t touching = 0;  // they bounce: count the wall contacts over the run
  for (int k = 0; k < 6000; ++k) {
    one->advance(1);
    touching += one->stats().contacts_wall;
  }
  restarted->advance(3000);
  const StateBlob blob = restarted->save_state();
  auto resumed = make();
  resumed->load_state(blob);
  resumed->advance(3000);
  REQUIRE(touching > 100);
  const auto a = one->flat_state(), c = resumed->flat_state();
  CHECK(a.position == c.position);
  CHECK(a.velocity == c.velocity);
  CHECK(one->wall_force(0) == resumed->wall_force(0));
  CHECK(one->wall_axial_torque(0) == resumed->wall_axial_torque(0));
}

TEST_CASE("polyline walls: bad input is refused naming the parameter", "[polyline]") {
  using Catch::Contains;
  auto sim = scene();
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}})),
                    Contains("points") && Contains("at least 2"));
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {1, 0}}, false, {{1, 0.4}})),
                    Contains("arc radius of segment 1") && Contains("half the chord"));
  // Half circles whose end points come from cos and sin lie a few ulps more
  // than 2R apart: read as half circles, at every angle.
  const double big_r = 4e-3;
  for (int k = 0; k < 200; ++k) {
    const double a = 0.0314159 * k, c = big_r * std::cos(a), s = big_r * std::sin(a);
    INFO("end points at " << a << " rad");
    CHECK_NOTHROW(
        scene()->add_polyline_wall(polyline({{c, s}, {-c, -s}}, true, {{1, -big_r}, {2, -big_r}})));
  }
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {1, 0}}, false, {{2, 1}})),
                    Contains("arcs[1].segment = 2") && Contains("1 segments"));
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {1, 0}}, false, {{0, 1}})),
                    Contains("arcs[1].segment = 0"));
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {NAN, 0}})),
                    Contains("points[2]") && Contains("not finite"));
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {1, 0}}, false, {{1, NAN}})),
                    Contains("arcs[1].radius"));
  CHECK_THROWS_WITH(sim->add_polyline_wall(polyline({{0, 0}, {0, 0}})),
                    Contains("segment 1") && Contains("zero length"));
  PolylineWallSpec moving = polyline({{0, 0}, {1, 0}});
  PolylineWallSpec open_solid = polyline({{0, 0}, {1, 0}, {1, 1}});
  open_solid.solid = true;
  CHECK_THROWS_WITH(sim->add_polyline_wall(open_solid), Contains("solid") && Contains("closed"));
  moving.angular_velocity = INFINITY;
  CHECK_THROWS_WITH(sim->add_polyline_wall(moving), Contains("angular_velocity"));
  CHECK(sim->wall_count() == 0);
  Simulation<3> s3;
  s3.add_material({"w", 0, 5e7, 0.3, 0});
  PolylineWallSpec in3 = polyline({{0, 0}, {1, 0}});
  in3.material = 0;
  CHECK_THROWS_WITH(s3.add_polyline_wall(in3), Contains("wall_mesh"));
}

TEST_CASE("polyline surface: a chain's end resting on its own floor is no second contact",
          "[polyline]") {
  // A floor from (-1, 0) to (1, 0), down, back under it and up to end on, or
  // a rounding below, the floor's middle (an outline drawn without closing it
  // exactly): a disk on the floor beside that end rests on the floor alone, as
  // on a plain floor, not also on the end's corner.
  const double r = 0.1, depth = 1e-4;
  for (const double below : {0.0, 1e-13, 1e-9, 0.5e-3 * r}) {
    Polyline line;
    line.points = {{-1, 0}, {1, 0}, {1, -1}, {0, -1}, {0, -below}};
    PolylineSurface s(line);
    PolylineHit hits[PolylineSurface::max_hits];
    for (const double x : {0.0, 0.002, 0.01}) {
      INFO("end " << below << " m below the floor, disk at x = " << x);
      REQUIRE(s.contacts(Vector2d(x, r - depth), r, r, hits) == 1);
      CHECK(hits[0].distance == Approx(r - depth).epsilon(1e-12));
      CHECK(hits[0].feature == MeshFeature::face);
    }
  }
}

TEST_CASE("polyline walls: a disk placed inside a solid polyline is warned of, naming the wall",
          "[polyline]") {
  // Its contact throws the centre out through the nearest side, as fast as the
  // overlap drives it: the scene is told where, at the start, when a particle
  // is added during a run, and when one is moved there.
  auto sim = scene("linear");
  std::vector<std::string> warnings;
  sim->set_warning_handler([&](const std::string& w) { warnings.push_back(w); });
  PolylineWallSpec post =
      polyline({{-5e-3, -5e-3}, {5e-3, -5e-3}, {5e-3, 5e-3}, {-5e-3, 5e-3}}, true);
  post.name = "post";
  post.solid = true;
  sim->add_polyline_wall(post);
  sim->add_particle(disk({1e-3, 0, 0}, {0, 0, 0}, 1e-4));
  const std::int64_t outside = sim->add_particle(disk({2e-2, 0, 0}, {0, 0, 0}, 1e-4));
  sim->advance(1);
  auto said = [&](const std::string& what) {
    for (const auto& w : warnings)
      if (w.find(what) != std::string::npos &&
          w.find("inside solid wall 'post'") != std::string::npos)
        return true;
    return false;
  };
  CHECK(said("particle 0 at (0.001"));
  CHECK(said("starts inside"));
  sim->add_particle(disk({0, 2e-3, 0}, {0, 0, 0}, 1e-4));
  CHECK(said("particle added at (0, 0.002)"));
  sim->set_position(outside, {0, -1e-3, 0});
  CHECK(said("set_position: particle 1"));
  // Outside it: nothing said.
  const std::size_t before = warnings.size();
  sim->add_particle(disk({3e-2, 0, 0}, {0, 0, 0}, 1e-4));
  sim->advance(1);
  CHECK(warnings.size() == before);
}
