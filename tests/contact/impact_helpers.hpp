// Two-sphere and sphere-wall impacts run through the real engine, for tests
// that compare with closed forms.
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>
#include <utility>

#include "contact/parameters.hpp"
#include "engine/simulation.hpp"

namespace granule::test {

struct ImpactResult {
  double restitution = 0;         // normal
  double force_duration = 0;      // s with N > 0
  double geometric_duration = 0;  // s with overlap > 0
  double max_overlap = 0;
  double max_normal = 0;
  double rebound_tangential = 0;  // relative tangential velocity after
  double spin_a = 0, spin_b = 0;  // z components after
  double dt = 0;
  std::int64_t steps = 0;
};

struct ImpactSetup {
  std::string model = "walton_braun";
  ParamValues params;
  double radius = 0.2e-3, density = 1200;
  double young = 0, poisson = 0;  // for Hertzian models (the wall gets the same)
  double velocity = 1.0;          // relative
  double angle_deg = 0;
  double spin = 0;
  double steps_per_contact = 40;
  bool wall = false;
  double skin = 0;
  // Called after every step with the simulation (for per-step checks).
  std::function<void(SimulationBase&)> each_step;
  std::int64_t sort_at_step = -1;  // re-sort particle storage at this step
  bool batched = true;             // the batched kernels where a model has them
};

template <int D>
ContactState<D> state(const Vec<D>& normal, double overlap, const Vec<D>& tangential_velocity,
                      double dt, double effective_mass = 1e-8, double effective_radius = 1e-4) {
  ContactState<D> c;
  c.normal = normal;
  c.overlap = overlap;
  c.normal_velocity = 0;
  c.tangential_velocity = tangential_velocity;
  c.effective_mass = effective_mass;
  c.inv_mass_sum = 1.0 / effective_mass;
  c.effective_radius = effective_radius;
  c.dt = dt;
  return c;
}

// Drives model M's 2D form and its 3D vector form through the same in-plane
// contact (z = 0) that turns back and forth, loads and unloads, and slides
// with reversals (slip speed amplitude `slip`, m/s; the normal velocity that
// goes with the overlap when `with_normal_rate`); the 2D form keeps its
// tangential state along t = (-n_y, n_x), so both must agree to round-off.
// Returns {largest difference of the tangential forces, largest force}, N.
template <typename M>
std::pair<double, double> in_plane_2d_3d_difference(const typename M::Params& p, double slip,
                                                    double dt, bool with_normal_rate) {
  typename M::template History<2> h2;
  typename M::template History<3> h3;
  double worst = 0, largest = 0;
  for (int k = 0; k < 6000; ++k) {
    const double angle = 0.4 * std::sin(1e-3 * k);               // the contact turns
    const double overlap = 1e-6 * (1.2 + std::sin(2.3e-3 * k));  // loads and unloads
    const double slip_speed = slip * std::cos(3.1e-3 * k);       // reverses often
    const Eigen::Vector2d n2(std::cos(angle), std::sin(angle)), t2(-n2.y(), n2.x());
    const Eigen::Vector3d n3(n2.x(), n2.y(), 0), t3(t2.x(), t2.y(), 0);
    auto c2 = state<2>(n2, overlap, Eigen::Vector2d(slip_speed * t2), dt);
    auto c3 = state<3>(n3, overlap, Eigen::Vector3d(slip_speed * t3), dt);
    if (with_normal_rate)
      c2.normal_velocity = c3.normal_velocity = 2.3e-3 * 1e-6 * std::cos(2.3e-3 * k) / dt;
    const auto f2 = M::template force<2>(p, h2, c2);
    const auto f3 = M::template force<3>(p, h3, c3);
    REQUIRE(f2.normal == f3.normal);
    worst = std::max(
        worst, (Eigen::Vector3d(f2.tangential.x(), f2.tangential.y(), 0) - f3.tangential).norm());
    largest = std::max(largest, f3.tangential.norm());
  }
  return {worst, largest};
}

template <int D>
ImpactResult run_impact(const ImpactSetup& s) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", s.density, s.young, s.poisson, 0});
  sim.add_material({"w", 0, s.young, s.poisson, 0});
  sim.set_contact("p", "p", s.model, s.params);
  sim.set_contact("p", "w", s.model, s.params);
  sim.set_steps_per_contact(s.steps_per_contact);
  if (s.skin > 0) sim.set_skin(s.skin);
  sim.set_record_contacts(true);
  sim.set_batched_contacts(s.batched);
  const double r = s.radius, gap = 1e-3 * r;
  const double ca = std::cos(s.angle_deg * pi / 180), sa = std::sin(s.angle_deg * pi / 180);
  ParticleSpec a, b;
  a.radius = b.radius = r;
  a.material = b.material = 0;
  a.spin = b.spin = {0, 0, s.spin};
  if (s.wall) {
    WallSpec w;
    w.name = "wall";
    w.material = 1;
    w.normal = {-1, 0, 0};
    sim.add_wall(w);
    a.position = {-r - gap, 0, 0};
    a.velocity = {s.velocity * ca, s.velocity * sa, 0};
    sim.add_particle(a);
  } else {
    a.position = {-r - gap / 2, 0, 0};
    a.velocity = {s.velocity * ca / 2, s.velocity * sa / 2, 0};
    b.position = {r + gap / 2, 0, 0};
    b.velocity = {-s.velocity * ca / 2, -s.velocity * sa / 2, 0};
    sim.add_particle(a);
    sim.add_particle(b);
  }
  auto rel = [&](double& vn, double& vt) {
    Triple pa = sim.position(0), va = sim.velocity(0);
    Triple pb{r + 0.0, 0, 0}, vb{0, 0, 0};
    double nx = -1, ny = 0;
    if (!s.wall) {
      pb = sim.position(1), vb = sim.velocity(1);
      double dx = pa[0] - pb[0], dy = pa[1] - pb[1], l = std::hypot(dx, dy);
      nx = dx / l, ny = dy / l;
    }
    double vx = vb[0] - va[0], vy = vb[1] - va[1];
    vn = vx * nx + vy * ny;
    vt = -vx * ny + vy * nx;
  };
  double vn0, vt0;
  rel(vn0, vt0);
  sim.prepare();
  ImpactResult out;
  out.dt = sim.time_step();
  bool seen = false;
  for (std::int64_t k = 0; k < 10000000; ++k) {
    if (k == s.sort_at_step) sim.sort_particles();
    sim.advance(1);
    if (s.each_step) s.each_step(sim);
    auto contacts = sim.contacts();
    if (contacts.empty()) {
      if (seen) break;
      continue;
    }
    seen = true;
    const auto& c = contacts[0];
    out.geometric_duration += out.dt;
    if (c.normal_force > 0) out.force_duration += out.dt;
    out.max_overlap = std::max(out.max_overlap, c.overlap);
    out.max_normal = std::max(out.max_normal, c.normal_force);
  }
  double vn1, vt1;
  rel(vn1, vt1);
  out.restitution = -vn1 / vn0;
  out.rebound_tangential = vt1;
  out.spin_a = sim.spin(0)[2];
  out.spin_b = s.wall ? 0 : sim.spin(1)[2];
  out.steps = sim.step_count();
  return out;
}

}  // namespace granule::test
