// Mesh walls in the engine: a sphere meets a flat mesh exactly as it meets the
// analytic plane (every contact model), rolls across shared edges and
// vertices with one contact and the plane's force, sits in a concave corner
// as against two planes, is dragged along by a turning mesh, and a run is
// the same on any number of threads and across a checkpoint.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>

#include "engine/simulation.hpp"
#include "io/mesh_file.hpp"
#include "mesh_helpers.hpp"

using namespace granule;

namespace {
struct Law {
  std::string model;
  ParamValues params;
  double young = 0, poisson = 0;
};
Law linear() {
  return {"linear", {{"k_normal", 2000}, {"restitution", 0.7}, {"friction", 0.4}}};
}
Law hertz() {
  return {"hertz_mindlin", {{"restitution", 0.6}, {"friction", 0.35}}, 5e7, 0.3};
}
Law walton() {
  return {"walton_braun", {{"k_load", 2000}, {"restitution", 0.8}, {"friction", 0.4}}};
}

std::unique_ptr<Simulation<3>> scene(const Law& law, double steps_per_contact = 60) {
  auto sim = std::make_unique<Simulation<3>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", 2500, law.young, law.poisson, 0});
  sim->add_material({"w", 0, law.young, law.poisson, 0});
  sim->set_contact("p", "p", law.model, law.params);
  sim->set_contact("p", "w", law.model, law.params);
  sim->set_steps_per_contact(steps_per_contact);
  sim->set_record_contacts(true);
  return sim;
}
void add_mesh(Simulation<3>& sim, io::TriangleMesh m, const std::string& name = "mesh",
              Triple omega_axis = {0, 0, 1}, double omega = 0) {
  io::MeshFileReport report;
  io::clean_mesh(m, report);
  MeshWallSpec s;
  s.name = name;
  s.file = "(memory)";
  s.material = 1;
  s.axis = omega_axis;
  s.angular_velocity = omega;
  sim.add_mesh_wall(s, std::move(m));
}
void add_plane(Simulation<3>& sim, const std::string& name, Triple normal) {
  WallSpec w;
  w.name = name;
  w.material = 1;
  w.normal = normal;
  sim.add_wall(w);
}
ParticleSpec sphere(Triple x, Triple v, Triple w, double r = 1e-3) {
  ParticleSpec p;
  p.position = x, p.velocity = v, p.spin = w, p.radius = r, p.material = 0;
  return p;
}
bool near_equal(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max(std::abs(a), std::abs(b)) + 1e-300;
}

struct Impact {
  double restitution = 0, peak_force = 0, vx = 0, spin_y = 0;
  std::int64_t steps_in_contact = 0;
  int most_contacts = 0;
};
// An oblique impact with spin, landing on (x0, y0) of the floor z = 0.
Impact drop(const Law& law, bool mesh, double x0, double y0) {
  auto sim = scene(law);
  if (mesh)
    add_mesh(*sim, test::flat_grid(0.01, 1));  // two triangles, diagonal through the origin
  else
    add_plane(*sim, "floor", {0, 0, 1});
  const double r = 1e-3, vn = 0.3;
  sim->add_particle(sphere({x0, y0, r + 1e-5}, {0.2, 0, -vn}, {0, 40, 30}));
  sim->prepare();
  Impact out;
  bool seen = false;
  for (int k = 0; k < 200000; ++k) {
    sim->advance(1);
    const auto c = sim->contacts();
    out.most_contacts = std::max(out.most_contacts, static_cast<int>(c.size()));
    if (c.empty()) {
      if (seen) break;
      continue;
    }
    seen = true;
    ++out.steps_in_contact;
    out.peak_force = std::max(out.peak_force, c[0].normal_force);
  }
  out.restitution = sim->velocity(0)[2] / vn;
  out.vx = sim->velocity(0)[0];
  out.spin_y = sim->spin(0)[1];
  return out;
}
}  // namespace

TEST_CASE("mesh walls: an impact on a two-triangle mesh is the impact on the plane", "[mesh]") {
  for (const Law& law : {linear(), hertz(), walton()}) {
    // Inside a triangle, and on the diagonal both triangles share.
    for (auto [x0, y0] : {std::pair{-0.004, 0.002}, std::pair{0.0, 0.0}}) {
      INFO(law.model << " at " << x0 << ", " << y0);
      const Impact plane = drop(law, false, x0, y0), mesh = drop(law, true, x0, y0);
      REQUIRE(plane.steps_in_contact > 20);
      CHECK(mesh.most_contacts == 1);
      CHECK(mesh.steps_in_contact == plane.steps_in_contact);
      CHECK(near_equal(mesh.restitution, plane.restitution, 1e-9));
      CHECK(near_equal(mesh.peak_force, plane.peak_force, 1e-9));
      CHECK(near_equal(mesh.vx, plane.vx, 1e-9));
      CHECK(near_equal(mesh.spin_y, plane.spin_y, 1e-9));
      CHECK(plane.restitution > 0.3);  // it did bounce
    }
  }
}

TEST_CASE("mesh walls: rolling across shared edges and vertices, one contact, the plane's force",
          "[mesh]") {
  const Law law = linear();
  const double r = 1e-3, g = 9.81, v = 0.05;
  // Along a grid line (through the vertices every 2.5 mm, on edges between
  // them) and across the grid at an angle (through edges and diagonals).
  for (auto path : {std::tuple{v, 0.0, 0.0}, std::tuple{v, 0.37 * v, 0.0003}}) {
    const double vx = std::get<0>(path), vy = std::get<1>(path), y0 = std::get<2>(path);
    INFO("velocity " << vx << ", " << vy);
    auto roll = [&](bool mesh) {
      auto sim = scene(law);
      sim->set_gravity({0, 0, -g});
      if (mesh)
        add_mesh(*sim, test::flat_grid(0.01, 8));
      else
        add_plane(*sim, "floor", {0, 0, 1});
      const double sink = sphere_mass(r, 2500) * g / 2000;  // resting overlap
      sim->add_particle(sphere({-0.006, y0, r - sink}, {vx, vy, 0}, {-vy / r, vx / r, 0}));
      sim->prepare();
      std::vector<double> fn;
      std::vector<int> count;
      const std::int64_t steps = static_cast<std::int64_t>(0.2 / sim->time_step());
      for (std::int64_t k = 0; k < steps; ++k) {
        sim->advance(1);
        const auto c = sim->contacts();
        count.push_back(static_cast<int>(c.size()));
        fn.push_back(c.empty() ? 0 : c[0].normal_force);
      }
      return std::tuple{fn, count, sim->position(0)};
    };
    const auto [plane_fn, plane_count, plane_end] = roll(false);
    const auto [mesh_fn, mesh_count, mesh_end] = roll(true);
    REQUIRE(mesh_end[0] - (-0.006) > 0.008);  // crossed three grid lines or more
    bool one_each_step = true, same_force = true;
    double largest_jump = 0;
    for (std::size_t k = 0; k < mesh_fn.size(); ++k) {
      one_each_step = one_each_step && mesh_count[k] == 1;
      same_force = same_force && near_equal(mesh_fn[k], plane_fn[k], 1e-9);
      if (k) largest_jump = std::max(largest_jump, std::abs(mesh_fn[k] - mesh_fn[k - 1]));
    }
    CHECK(one_each_step);
    CHECK(same_force);
    INFO("largest step-to-step change of the normal force " << largest_jump);
    CHECK(largest_jump < 1e-3 * sphere_mass(r, 2500) * g);
    CHECK(near_equal(mesh_end[0], plane_end[0], 1e-9));
    CHECK(near_equal(mesh_end[1], plane_end[1], 1e-9));
  }
}

TEST_CASE("mesh walls: a concave corner holds a sphere with two contacts, as two planes do",
          "[mesh]") {
  const Law law = hertz();
  auto run = [&](bool mesh) {
    auto sim = scene(law);
    sim->set_gravity({-6, 0, -8});  // into both faces
    if (mesh) {
      add_mesh(*sim, test::corner(0.01));
    } else {
      add_plane(*sim, "floor", {0, 0, 1});
      add_plane(*sim, "side", {1, 0, 0});
    }
    const double r = 1e-3;
    sim->add_particle(sphere({r + 2e-5, 0.001, r + 5e-5}, {0, 0, 0}, {0, 0, 0}));
    sim->prepare();
    std::vector<std::vector<double>> forces;
    std::vector<int> count;
    for (int k = 0; k < 20000; ++k) {
      sim->advance(1);
      auto c = sim->contacts();
      std::vector<double> f;
      for (auto& x : c) f.push_back(x.normal_force);
      std::sort(f.begin(), f.end());
      forces.push_back(f);
      count.push_back(static_cast<int>(c.size()));
    }
    return std::tuple{forces, count, sim->position(0), sim->wall_force(0)};
  };
  const auto [pf, pc, px, pw] = run(false);
  const auto [mf, mc, mx, mw] = run(true);
  REQUIRE(pc.back() == 2);
  CHECK(mc.back() == 2);
  bool same = true;
  for (std::size_t k = 0; k < pf.size(); ++k) {
    same = same && mc[k] == pc[k];
    for (std::size_t j = 0; same && j < pf[k].size(); ++j)
      same = near_equal(mf[k][j], pf[k][j], 1e-9);
  }
  CHECK(same);
  for (int d = 0; d < 3; ++d) CHECK(std::abs(mx[d] - px[d]) <= 1e-9 * 1e-3);
  // At rest: the mesh carries the sphere's weight in both directions.
  const double m = sphere_mass(1e-3, 2500);
  CHECK(mw[0] == Approx(-6 * m).epsilon(1e-3));
  CHECK(mw[2] == Approx(-8 * m).epsilon(1e-3));
}

TEST_CASE("mesh walls: a turning fan of triangles drags a resting sphere to its surface speed",
          "[mesh]") {
  const Law law = linear();
  const double r = 1e-3, g = 9.81, omega = 4, rho = 0.01;
  auto sim = scene(law);
  sim->set_gravity({0, 0, -g});
  add_mesh(*sim, test::fan_disk(0.03, 24), "turntable", {0, 0, 1}, omega);
  const double sink = sphere_mass(r, 2500) * g / 2000;
  sim->add_particle(sphere({rho, 0, r - sink}, {0, 0, 0}, {0, 0, 0}));
  sim->prepare();
  const std::int64_t steps = static_cast<std::int64_t>(0.1 / sim->time_step());
  sim->advance(steps);
  // The contact point's velocity, v + w x (-r z), against the surface's there.
  const Triple x = sim->position(0), v = sim->velocity(0), w = sim->spin(0);
  const Eigen::Vector3d cv = Eigen::Vector3d(v[0], v[1], v[2]) +
                             Eigen::Vector3d(w[0], w[1], w[2]).cross(Eigen::Vector3d(0, 0, -r));
  const Eigen::Vector3d surface =
      omega * Eigen::Vector3d(0, 0, 1).cross(Eigen::Vector3d(x[0], x[1], 0));
  INFO("contact point " << cv.transpose() << " surface " << surface.transpose());
  REQUIRE(surface.norm() > 0.5 * omega * rho);  // still on the table, not flung to its rim
  CHECK((cv - surface).norm() < 0.02 * surface.norm());
  CHECK(cv.norm() > 0.5 * omega * rho);  // it moves: the surface velocity reached it
  // The table carries the sphere's weight.
  CHECK(sim->wall_force(0)[2] == Approx(-sphere_mass(r, 2500) * g).epsilon(0.01));
}

namespace {
// Spheres poured onto a tilted, turning and sliding mesh: enough contacts,
// several per particle at times, for the order of sums to matter.
std::unique_ptr<Simulation<3>> pour(int threads) {
  Law law = walton();
  law.params["restitution"] = 0.3;  // they settle in the bowl rather than bounce out
  auto sim = scene(law, 40);
  sim->set_gravity({0, 0, -9.81});
  sim->set_threads(threads);
  sim->set_parallel_thresholds(1, 1);
  io::TriangleMesh floor = test::flat_grid(0.01, 6);
  for (auto& x : floor.vertices) x.z() = 0.2 * x.x() + 0.1 * x.y() + 0.3 * x.x() * x.x() / 0.01;
  add_mesh(*sim, floor, "bowl", {0.1, 0.2, 1}, 3);
  for (int k = 0; k < 60; ++k)
    sim->add_particle(sphere(
        {-0.006 + 0.0021 * (k % 6), -0.006 + 0.0021 * (k / 6 % 6), 0.004 + 0.0021 * (k / 36)},
        {0, 0, -0.3}, {0, 0, 0}, 0.9e-3));
  sim->prepare();
  return sim;
}
}  // namespace

TEST_CASE("mesh walls: the same run on 1 and 3 threads and across a checkpoint", "[mesh]") {
  auto one = pour(1), three = pour(3), restarted = pour(1);
  one->advance(16000);
  three->advance(16000);
  restarted->advance(8000);
  const StateBlob blob = restarted->save_state();
  auto resumed = pour(1);
  resumed->load_state(blob);
  resumed->advance(8000);
  REQUIRE(one->stats().contacts_wall > 0);
  const auto a = one->flat_state(), b = three->flat_state(), c = resumed->flat_state();
  CHECK(a.position == b.position);
  CHECK(a.position == c.position);
  CHECK(a.velocity == c.velocity);
  CHECK(one->wall_force(0) == three->wall_force(0));
  CHECK(one->wall_force(0) == resumed->wall_force(0));
  CHECK(one->wall_axial_torque(0) == resumed->wall_axial_torque(0));
}

TEST_CASE("mesh walls: along a periodic axis a mesh must run straight, a sloping one is refused",
          "[mesh]") {
  // Periodic along x over 10 mm: a flat floor spanning the period repeats with
  // it; a ramp rising along x (z = 0.1 x) spans it too but is 1 mm higher at one
  // end than at the other, where a particle that wraps would fall through it.
  for (const bool ramp : {false, true}) {
    auto sim = scene(linear());
    sim->set_periodic(0, 0, 10e-3);
    io::TriangleMesh m = test::flat_grid(0.012, 4);
    if (ramp)
      for (auto& v : m.vertices) v[2] = 0.1 * v[0];
    add_mesh(*sim, m, "floor");
    sim->add_particle(sphere({5e-3, 0, 2e-3}, {0, 0, 0}, {0, 0, 0}));
    INFO("ramp " << ramp);
    if (ramp)
      CHECK_THROWS_WITH(sim->prepare(), Catch::Contains("wall 'floor'") &&
                                            Catch::Contains("slopes along the axis") &&
                                            Catch::Contains("periodic along x"));
    else
      CHECK_NOTHROW(sim->prepare());
  }
}

TEST_CASE("mesh walls: a plate moving at a sphere at rest meets it whichever way it moves",
          "[mesh]") {
  // No gravity, the sphere at rest 9 mm from the plate: it is found only through
  // the plate's own travel, which the lists must count along -z as along +z
  // (a signed step cancelled the travel counted for a velocity along -x).
  const double speed = 0.5;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      auto sim = scene(linear());
      io::TriangleMesh plate = test::flat_grid(0.01, 2, -sign * 0.01);
      for (auto& v : plate.vertices) std::swap(v[2], v[axis]);  // the plate across `axis`
      add_mesh(*sim, std::move(plate));
      sim->add_particle(sphere({0, 0, 0}, {0, 0, 0}, {0, 0, 0}));
      Triple velocity{0, 0, 0};
      velocity[axis] = sign * speed;
      sim->set_wall_velocity(0, velocity);
      sim->prepare();
      sim->advance(static_cast<std::int64_t>(0.03 / sim->time_step()));
      INFO("axis " << axis << ", moving " << sign);
      // Struck by an immovable wall at `speed`: (1 + e) times it, e = 0.7 (to 2 %, n = 60).
      CHECK(sim->velocity(0)[axis] == Approx(sign * 1.7 * speed).epsilon(0.02));
    }
}

// As an analytic wall: a mesh moving farther than the smallest radius in one
// step towards a particle within that reach stops the run (it passed through
// silently), one far off, pulled away or sliding along itself does not; a
// paddle turning so fast that its tip sweeps over a particle stops it too.
TEST_CASE("mesh walls: a mesh that would step over a particle stops the run, one far off does not",
          "[mesh]") {
  auto run = [](Triple velocity, double distance, double omega = 0) {
    auto sim = scene(linear());
    sim->set_time_step(1e-5);
    add_mesh(*sim, test::flat_grid(0.01, 2, -distance), "plate", {1, 0, 0}, omega);
    sim->set_wall_velocity(0, velocity);
    sim->add_particle(sphere({0, 0.005, 0}, {0, 0, 0}, {0, 0, 0}));
    sim->advance(3);
  };
  // 260 m/s: 2.6 mm a step, 2.6 radii (the plate crossed the particle unseen).
  CHECK_THROWS_WITH(run({0, 0, 260}, 1.5e-3),
                    Catch::Contains("wall 'plate' moves") &&
                        Catch::Contains("more than the smallest free particle's radius"));
  CHECK_THROWS_WITH(run({0, 0, -260}, -1.5e-3), Catch::Contains("wall 'plate' moves"));
  CHECK_NOTHROW(run({0, 0, 260}, 1.0));      // a metre off
  CHECK_NOTHROW(run({0, 0, -260}, 1.5e-3));  // pulled away
  CHECK_NOTHROW(run({260, 0, 0}, 1.5e-3));   // sliding along under it
  CHECK_NOTHROW(run({0, 0, 0.1}, 1.5e-3));   // slow
  // Turning about x through the origin at 3e4 rad/s: the plate's point under the
  // particle, 5 mm from the axis, rises 1.5 mm a step (the corners, 14 mm out, 4.3 mm).
  CHECK_THROWS_WITH(run({0, 0, 0}, 1.5e-3, 3e4), Catch::Contains("wall 'plate' moves"));
  CHECK_NOTHROW(run({0, 0, 0}, 1.5e-3, -3e4));  // turning away
  CHECK_NOTHROW(run({0, 0, 0}, 1.5e-3, 1));
}
