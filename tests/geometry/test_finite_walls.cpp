// Finite analytic walls (src/geometry/finite_walls.hpp) against closed forms:
// the clearance and normal at a face, a rim and a hole's edge, worked by hand;
// a sphere falling through a disk's hole against one landing on the disk
// (free fall, then Hertz's static overlap); a sphere rolling off a bounded
// plane's edge (the force never jumps); a frictionless ball sliding down a
// cone's inside (g cos(alpha)); a translating disk carrying a sphere up to
// 2/7 of its speed (the belt problem) and a turning one pushing it along
// omega x r; and the bad inputs, each refused naming its parameter.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;
using Catch::Matchers::Contains;

namespace {
constexpr double g = 9.81, rp = 2e-3, rho = 2500, young = 1e7, poisson = 0.3;

// A 3D scene of one material pair under gravity along -z, Hertz-Mindlin.
void scene(Simulation<3>& sim, double restitution, double friction) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"glass", rho, young, poisson, 0});
  sim.add_material({"steel", 7800, young, poisson, 0});
  const ParamValues law{{"restitution", restitution}, {"friction", friction}};
  sim.set_contact("glass", "glass", "hertz_mindlin", law);
  sim.set_contact("glass", "steel", "hertz_mindlin", law);
  sim.set_gravity({0, 0, -g});
}

WallSpec disk(double radius, double inner) {
  WallSpec w;
  w.name = "disk", w.type = WallType::disk, w.material = 1;
  w.normal = {0, 0, 1}, w.radius = radius, w.inner_radius = inner;
  return w;
}

std::int64_t sphere(Simulation<3>& sim, Triple x, Triple v = {0, 0, 0}, Triple spin = {0, 0, 0}) {
  ParticleSpec p;
  p.position = x, p.velocity = v, p.spin = spin, p.radius = rp, p.material = 0;
  return sim.add_particle(p);
}

double mass() {
  return sphere_mass(rp, rho);
}
// Hertz's static overlap of a sphere of weight m g on a flat wall:
// m g = (4/3) E* sqrt(R) delta^1.5, E* = E / (2 (1 - nu^2)) for two equal materials.
double static_overlap() {
  const double e_star = young / (2 * (1 - poisson * poisson));
  return std::pow(3 * mass() * g / (4 * e_star * std::sqrt(rp)), 2.0 / 3.0);
}

// Grains ("g") and a massless wall material ("w"), a stiff linear law between them:
// the moving-wall checks' scenes, where only positions matter.
void linear_grains(Simulation<3>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"g", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  sim.set_contact("g", "g", "linear", {{"k_normal", 1e4}, {"restitution", 0.5}});
  sim.set_contact("g", "w", "linear", {{"k_normal", 1e4}, {"restitution", 0.5}});
}

void check_normal(const Vec<3>& n, const Vec<3>& expected) {
  CHECK((n - expected).norm() < 1e-12);
}
}  // namespace

TEST_CASE("finite walls: clearance and normal at a disk's face, rim and hole edge") {
  Simulation<3> sim;
  scene(sim, 0.5, 0);
  WallSpec w = disk(0.05, 0.01);
  w.center = {0.1, 0, 0};
  sim.add_wall(w);
  const Wall<3>& d = sim.walls()[0];
  const double r = 0.003;
  Vec<3> n, sv, lever;
  // Face, from above and from below: the overlap is r - |z|, the normal +-z.
  CHECK(d.contact(Vec<3>(0.13, 0, 0.002), r, n, sv, lever) == Approx(0.001).epsilon(1e-12));
  check_normal(n, {0, 0, 1});
  CHECK(d.contact(Vec<3>(0.13, 0, -0.002), r, n, sv, lever) == Approx(0.001).epsilon(1e-12));
  check_normal(n, {0, 0, -1});
  // Outer rim, at 45 degrees round the axis: a 3-4-5 triangle from the rim point.
  const double c = std::sqrt(0.5);
  const Vec<3> rim_x(0.1 + 0.053 * c, 0.053 * c, 0.004);
  CHECK(d.clearance(rim_x, r) == Approx(0.002).epsilon(1e-9));
  d.contact(rim_x, r, n, sv, lever);
  check_normal(n, Vec<3>(0.6 * c, 0.6 * c, 0.8));
  // The hole's edge: the normal leans into the hole.
  const Vec<3> hole_x(0.1 + 0.007, 0, -0.004);
  CHECK(d.clearance(hole_x, r) == Approx(0.002).epsilon(1e-9));
  d.contact(hole_x, r, n, sv, lever);
  check_normal(n, {-0.6, 0, -0.8});
  // A flat face gives R* = r.
  CHECK(d.effective_radius(Vec<3>(0.13, 0, 0.002), r) == r);
}

TEST_CASE("finite walls: a rectangle's face, edge and corner, a tube's faces and rim") {
  Simulation<3> sim;
  scene(sim, 0.5, 0);
  WallSpec p;
  p.name = "plate", p.type = WallType::plane, p.material = 1, p.bounded = true;
  p.normal = {0, 0, 1}, p.size_a = 0.2, p.size_b = 0.1, p.side = {1, 1, 0};  // a along (1,1)/sqrt2
  sim.add_wall(p);
  WallSpec t;
  t.name = "tube", t.type = WallType::cylinder, t.material = 1, t.bounded = true;
  t.radius = 0.05, t.z_lo = 0, t.z_hi = 0.1;
  sim.add_wall(t);
  const Wall<3>& plate = sim.walls()[0];
  const Wall<3>& tube = sim.walls()[1];
  const double r = 0.003, c = std::sqrt(0.5);
  const Vec<3> a(c, c, 0), b(-c, c, 0);  // the sides' directions
  Vec<3> n, sv, lever;
  CHECK(plate.clearance(a * 0.09 + b * 0.04 + Vec<3>(0, 0, 0.001), r) == Approx(-0.002));
  // Past edge a (half side 0.1): 3-4-5 again.
  const Vec<3> edge_x = a * 0.103 + Vec<3>(0, 0, 0.004);
  CHECK(plate.clearance(edge_x, r) == Approx(0.002).epsilon(1e-9));
  plate.contact(edge_x, r, n, sv, lever);
  check_normal(n, a * 0.6 + Vec<3>(0, 0, 0.8));
  // Past the corner: the distance to the corner point.
  const Vec<3> corner_x = a * 0.101 + b * 0.052 + Vec<3>(0, 0, -0.002);
  CHECK(plate.clearance(corner_x, r) == Approx(3e-3 - r).margin(1e-12));
  // The tube from inside and outside its face: +-radial; the inside is concave.
  CHECK(tube.contact(Vec<3>(0, 0.047, 0.05), r, n, sv, lever) == Approx(0.0).margin(1e-12));
  check_normal(n, {0, -1, 0});
  CHECK(tube.effective_radius(Vec<3>(0, 0.047, 0.05), r) == Approx(r * 0.05 / (0.05 - r)));
  CHECK(tube.contact(Vec<3>(0.052, 0, 0.05), r, n, sv, lever) == Approx(0.001));
  check_normal(n, {1, 0, 0});
  CHECK(tube.effective_radius(Vec<3>(0.052, 0, 0.05), r) == Approx(r * 0.05 / (0.05 + r)));
  // Below the lower rim, inside: the normal points down and to the axis.
  const Vec<3> rim_x(0.047, 0, -0.004);
  CHECK(tube.clearance(rim_x, r) == Approx(0.002).epsilon(1e-9));
  tube.contact(rim_x, r, n, sv, lever);
  check_normal(n, {-0.6, 0, -0.8});
}

TEST_CASE("finite walls: a cone's inside face, its curvature and its narrow rim") {
  Simulation<3> sim;
  scene(sim, 0.5, 0);
  WallSpec w;
  w.name = "hopper", w.type = WallType::cone, w.material = 1;
  w.center = {0, 0, 0.2}, w.axis = {0, 0, 1}, w.z_lo = 0, w.z_hi = 0.1;
  w.radius_lo = 0.01, w.radius_hi = 0.06;  // tan(alpha) = 0.5 about the axis
  sim.add_wall(w);
  const Wall<3>& cone = sim.walls()[0];
  const double r = 0.003, cos_a = 2 / std::sqrt(5.0), sin_a = 1 / std::sqrt(5.0);
  Vec<3> n, sv, lever;
  // At z = 0.05 the surface is at rho = 0.035; a centre h inside it along the
  // radius is h cos(alpha) from the surface, along the inward normal.
  const double h = 0.002;
  const Vec<3> x(0, 0.035 - h, 0.25);
  CHECK(cone.contact(x, r, n, sv, lever) == Approx(r - h * cos_a).epsilon(1e-12));
  check_normal(n, {0, -cos_a, sin_a});
  // The circumferential curvature radius there: rho_c / cos(alpha), concave.
  const double rho_c = 0.035 - h * sin_a * sin_a, R = rho_c / cos_a;
  CHECK(cone.effective_radius(x, r) == Approx(r * R / (R - r)).epsilon(1e-12));
  // Just under the narrow end, on the axis side: the rim point (0.01, z = 0).
  const Vec<3> below(0.01 - 0.003, 0, 0.196);
  CHECK(cone.clearance(below, r) == Approx(0.002).epsilon(1e-9));
}

TEST_CASE("finite walls: a sphere falls through a disk's hole, and lands on the disk beside it") {
  // The same drop onto an infinite plane at the disk's height, for the resting height.
  double plane_rest = 0;
  {
    Simulation<3> sim;
    scene(sim, 0.3, 0.5);
    WallSpec floor;
    floor.name = "floor", floor.material = 1, floor.normal = {0, 0, 1};
    sim.add_wall(floor);
    sphere(sim, {0.03, 0, 0.01});
    sim.prepare();
    sim.advance(static_cast<std::int64_t>(0.3 / sim.time_step()));
    plane_rest = sim.position(0)[2];
  }
  for (bool through : {true, false}) {
    Simulation<3> sim;
    scene(sim, 0.3, 0.5);
    sim.add_wall(disk(0.05, 0.01));
    const double x0 = through ? 0.004 : 0.03, z0 = 0.01;
    sphere(sim, {x0, 0, z0});
    sim.prepare();
    const double dt = sim.time_step();
    std::int64_t touched = 0;
    const std::int64_t steps = static_cast<std::int64_t>(0.3 / dt);
    for (std::int64_t k = 0; k < steps; ++k) {
      sim.advance(1);
      touched += sim.stats().contacts_wall;
    }
    const double t = sim.time();
    if (through) {
      // r = 2 mm at 4 mm off the axis clears the 10 mm hole: free fall, in the
      // integrator's discrete form (kick, then drift: z_n = z0 - g dt^2 n (n + 1) / 2).
      CHECK(touched == 0);
      CHECK(sim.position(0)[2] == Approx(z0 - 0.5 * g * t * (t + dt)).epsilon(1e-9));
    } else {
      // Landed and settled: at rest on the face, the reaction its weight and the
      // height the infinite plane gives. Hertz's static overlap to 5 %: the
      // model's implicit dashpot lowers its static force by c_n dt / (2 m*), 4.5 % here.
      CHECK(touched > 0);
      CHECK(sim.wall_force(0)[2] == Approx(-mass() * g).epsilon(1e-4));
      CHECK(sim.position(0)[2] == Approx(plane_rest).epsilon(1e-12));
      CHECK(rp - sim.position(0)[2] == Approx(static_overlap()).epsilon(0.05));
    }
  }
}

TEST_CASE("finite walls: a sphere rolling off a bounded plane's edge feels no jump") {
  Simulation<3> sim;
  scene(sim, 0.3, 0.5);
  WallSpec p;
  p.name = "table", p.type = WallType::plane, p.material = 1, p.bounded = true;
  p.normal = {0, 0, 1}, p.size_a = 0.04, p.size_b = 0.04;
  sim.add_wall(p);
  // Rolling towards the edge at x = 0.02, resting at Hertz's overlap.
  const double v = 0.05;
  sphere(sim, {0.015, 0, rp - static_overlap()}, {v, 0, 0}, {0, v / rp, 0});
  sim.advance(1);
  const double weight = mass() * g;
  auto force = [&] {
    const Triple w = sim.wall_force(0);
    return std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  };
  double previous = force(), largest_jump = 0, lowest = weight;
  bool past_edge = false;
  for (int k = 0; k < 200000 && sim.position(0)[2] > -rp; ++k) {
    sim.advance(1);
    const double f = force();
    CHECK(sim.stats().contacts_wall <= 1);
    largest_jump = std::max(largest_jump, std::abs(f - previous));
    lowest = std::min(lowest, f);
    previous = f;
    past_edge = past_edge || sim.position(0)[0] > 0.02;
  }
  // It went over and off (the force fell to zero), never changing by more
  // than 2 % of its weight in one step.
  CHECK(past_edge);
  CHECK(lowest == 0);
  CHECK(largest_jump < 0.02 * weight);
}

TEST_CASE("finite walls: a frictionless ball slides down a cone's inside at g cos(alpha)") {
  Simulation<3> sim;
  scene(sim, 0.3, 0);
  WallSpec w;
  w.name = "hopper", w.type = WallType::cone, w.material = 1;
  w.axis = {0, 0, 1}, w.z_lo = 0, w.z_hi = 0.1, w.radius_lo = 0.01, w.radius_hi = 0.06;
  sim.add_wall(w);
  const double cos_a = 2 / std::sqrt(5.0), sin_a = 1 / std::sqrt(5.0);
  // On the surface at z = 0.08 (rho = 0.05), pressed in by the static overlap of
  // the normal load m g sin(alpha) on a concave face of curvature radius rho/cos(alpha).
  const double R = 0.05 / cos_a, r_star = rp * R / (R - rp);
  const double e_star = young / (2 * (1 - poisson * poisson));
  const double delta =
      std::pow(3 * mass() * g * sin_a / (4 * e_star * std::sqrt(r_star)), 2.0 / 3.0);
  const Vec<3> inward(-cos_a, 0, sin_a), start = Vec<3>(0.05, 0, 0.08) + inward * (rp - delta);
  sphere(sim, {start.x(), start.y(), start.z()});
  sim.prepare();
  const double t_end = 0.05;
  while (sim.time() < t_end) sim.advance(1);
  const double t = sim.time();
  const Vec<3> x(sim.position(0)[0], sim.position(0)[1], sim.position(0)[2]);
  const Vec<3> down(-sin_a, 0, -cos_a);  // along the generator, towards the narrow end
  CHECK((x - start).dot(down) == Approx(0.5 * g * cos_a * t * t).epsilon(2e-3));
  CHECK(std::abs(x.y()) < 1e-12);  // it stays in its meridian plane
}

TEST_CASE("finite walls: a moving disk carries its surface velocity into the contact") {
  SECTION("translating: a sphere at rest on it ends rolling at 2/7 of its speed") {
    Simulation<3> sim;
    scene(sim, 0.3, 0.3);
    WallSpec w = disk(0.5, 0);
    w.velocity = {0.1, 0, 0};
    sim.add_wall(w);
    sphere(sim, {0, 0, rp - static_overlap()});
    sim.prepare();
    while (sim.time() < 0.1) sim.advance(1);  // sliding ends after 2 v / (7 mu g) = 9.7 ms
    CHECK(sim.velocity(0)[0] == Approx(2.0 / 7.0 * 0.1).epsilon(2e-3));
    CHECK(sim.wall(0).center[0] == Approx(0.1 * sim.time()).epsilon(1e-9));
  }
  SECTION("turning: the friction on a sphere at rest points along omega x r") {
    Simulation<3> sim;
    scene(sim, 0.3, 0.3);
    WallSpec w = disk(0.5, 0);
    w.angular_velocity = 2;
    sim.add_wall(w);
    sphere(sim, {0.1, 0, rp - static_overlap()});
    sim.prepare();
    sim.advance(20);
    // Sliding: the tangential reaction on the disk is -mu N along +y (omega z x r).
    const Triple f = sim.wall_force(0);
    CHECK(f[1] == Approx(-0.3 * mass() * g).epsilon(2e-2));
    CHECK(std::abs(f[0]) < 1e-3 * std::abs(f[1]));
    CHECK(sim.wall_axial_torque(0) == Approx(0.1 * f[1]).epsilon(1e-2));
  }
}

TEST_CASE("finite walls: bad input is refused naming the parameter") {
  auto refused = [](WallSpec w, const std::string& words, int dimension = 3) {
    if (dimension == 3) {
      Simulation<3> sim;
      scene(sim, 0.5, 0);
      w.material = 1;
      CHECK_THROWS_WITH(sim.add_wall(w), Contains(words));
    } else {
      Simulation<2> sim;
      sim.add_material({"steel", 7800, young, poisson, 0});
      w.material = 0;
      CHECK_THROWS_WITH(sim.add_wall(w), Contains(words));
    }
  };
  WallSpec d = disk(0.01, 0.02);
  refused(d, "inner_radius must be >= 0 and less than radius");
  d = disk(0.01, 0);
  d.normal = {0, 0, 0};
  refused(d, "normal must be non-zero");
  d = disk(-1, 0);
  refused(d, "radius must be > 0");
  WallSpec c;
  c.name = "c", c.type = WallType::cone, c.axis = {0, 0, 1}, c.z_lo = 0, c.z_hi = 1;
  refused(c, "radii must not both be 0");
  c.radius_lo = 1, c.z_hi = 0;
  refused(c, "bounds = {lo, hi} must be finite with lo < hi");
  WallSpec p;
  p.name = "p", p.type = WallType::plane, p.bounded = true, p.normal = {0, 0, 1};
  p.size_a = 1, p.size_b = 1, p.side = {0, 0, 2};
  refused(p, "side must not be parallel to the normal");
  p.size_b = 0;
  refused(p, "size[2] must be > 0");
  WallSpec t;
  t.name = "t", t.type = WallType::cylinder, t.bounded = true, t.radius = 1, t.z_hi = 1;
  refused(t, "a cylinder in 2D is a circle about z and has no bounds", 2);
  WallSpec spin = disk(0.01, 0);
  spin.normal = {0, 1, 0}, spin.angular_velocity = 1;
  refused(spin, "leave angular_velocity out", 2);
}

// The wall loop skips a candidate surely clear of an unbounded cylinder
// (Wall::surely_apart) without its root and division: never one that
// contact() finds touching, and most of those that are clear by more than
// round-off; never a bounded cylinder or another wall.
TEST_CASE("walls: surely_apart never skips a touching candidate") {
  auto check = [](auto dimension) {
    constexpr int D = decltype(dimension)::value;
    using V = Vec<D>;
    for (const bool inside : {true, false}) {
      Wall<D> w;
      w.type = WallType::cylinder;
      w.center = V::Zero();
      w.center[0] = 1e-3;
      if constexpr (D == 3) w.axis = V(0, 0, 1);
      w.radius = 5e-3;
      w.inside = inside;
      int skipped = 0, clear = 0;
      const double r = 2e-4;
      // Centres swept across the surface in steps of 1e-9 m about the touching
      // distance, and far from it, at several angles.
      for (int a = 0; a < 16; ++a) {
        const double angle = 0.39 * a;
        for (int s = -400; s <= 400; ++s) {
          const double from_axis =
              (inside ? w.radius - r : w.radius + r) + s * 1e-9 + (s % 50 == 0 ? s * 1e-6 : 0.0);
          V x = w.center;
          x[0] += from_axis * std::cos(angle);
          x[1] += from_axis * std::sin(angle);
          if constexpr (D == 3) x[2] = 0.3e-3 * a;
          V n, surface_velocity, lever;
          const double overlap = w.contact(x, r, n, surface_velocity, lever);
          const bool apart = w.surely_apart(x, r);
          if (apart) {
            ++skipped;
            REQUIRE(overlap < 0);
          }
          if (overlap < -1e-8) ++clear;
        }
      }
      // Clear by more than 10 nm: each is skipped (the margin is ~5e-10 of the radius).
      CHECK(skipped >= clear);
      CHECK(clear > 0);
      w.bounded = true;
      V far = w.center;
      far[0] += inside ? 0.0 : 1.0;
      CHECK_FALSE(w.surely_apart(far, r));
      w.bounded = false;
      w.type = WallType::plane;
      CHECK_FALSE(w.surely_apart(far, r));
    }
  };
  check(std::integral_constant<int, 2>{});
  check(std::integral_constant<int, 3>{});
}

// A wall moving farther than the smallest radius in one step stops the run only
// with a particle within that reach: a rectangle sweeping through one does, one
// far off does not, nor an infinite plane moving away from the particles.
TEST_CASE("walls: a wall that would step over a particle stops the run, one far off does not",
          "[walls]") {
  auto run = [](bool bounded, Triple velocity, double distance) {
    Simulation<3> sim;
    linear_grains(sim);
    sim.set_time_step(1e-5);
    WallSpec w;
    w.name = "plate", w.material = 1, w.normal = {0, 0, 1}, w.velocity = velocity;
    w.point = {0, 0, -distance};
    w.bounded = bounded, w.size_a = w.size_b = 0.01;
    sim.add_wall(w);
    ParticleSpec p;
    p.radius = 1e-3, p.material = 0;
    sim.add_particle(p);
    sim.advance(1);
  };
  // 500 m/s: 5 mm a step, five radii.
  CHECK_THROWS_WITH(
      run(true, {0, 0, 500}, 2e-3),
      Contains("wall 'plate' moves") && Contains("more than the smallest free particle's radius"));
  CHECK_NOTHROW(run(true, {0, 0, 500}, 1.0));         // a metre off
  CHECK_NOTHROW(run(true, {0, 0, -500}, 1.0e-3));     // a gate it rests on pulled away
  CHECK_NOTHROW(run(true, {500, 0, 0}, 1.0e-3));      // a plate sliding along under it
  CHECK_NOTHROW(run(false, {0, 0, -500}, 1.1e-3));    // an infinite floor pulled away
  CHECK_NOTHROW(run(false, {500, 0, 0}, 1.1e-3));     // sliding along itself
  CHECK_THROWS_WITH(run(false, {0, 0, 500}, 1.1e-3),  // pushed up into the particle
                    Contains("wall 'plate' moves"));
}

// A periodic axis repeats the walls only while they span it: a rectangle that
// spans the period when the run begins and slides along the axis uncovers the
// seam, and particles fell through it unseen. The run stops once it does; a
// rectangle at rest and an infinite floor sliding along itself run on.
TEST_CASE(
    "walls: a finite floor sliding along the periodic axis stops the run once it "
    "uncovers the seam",
    "[walls]") {
  const double period = 0.01, radius = 1e-3;
  auto run = [&](bool bounded, double speed) {
    Simulation<3> sim;
    linear_grains(sim);
    sim.set_periodic(0, 0, period);
    sim.set_gravity({0, -9.81, 0});
    WallSpec w;
    w.name = "belt", w.material = 1, w.normal = {0, 1, 0}, w.side = {1, 0, 0};
    w.point = {period / 2, 0, 0}, w.velocity = {speed, 0, 0};
    w.bounded = bounded, w.size_a = period + 2 * radius + 1e-6, w.size_b = 0.02;
    sim.add_wall(w);
    ParticleSpec p;
    p.radius = radius, p.material = 0, p.position = {period / 2, radius, 0};
    sim.add_particle(p);
    sim.prepare();
    // (span - period) / speed = 0.02 s at 0.1 m/s: run for 0.05 s.
    while (sim.time() < 0.05) sim.advance(100);
    return sim.wall_force(0)[1];
  };
  CHECK_THROWS_WITH(run(true, 0.1), Catch::Contains("wall 'belt' has moved along the axis") &&
                                        Catch::Contains("periodic along x"));
  CHECK_NOTHROW(run(true, 0));
  CHECK_NOTHROW(run(false, 0.1));
}
