// How close does the engine come to a loop written for one scene? The 2D
// Mechanofusion base case (Table 4.1 geometry, 1500 particles) with linear
// spring-dashpot contacts everywhere, run (a) by the engine and (b) by a
// hand-specialised loop: the same physics (linear normal spring-dashpot,
// Coulomb-capped tangential spring with dashpot, torques at the contact point,
// leap-frog Eqs. 4.8-4.9), the same cell list (CellGrid) and skin, but nothing
// else: one model, 2D only, the tangential spring kept as a scalar along the
// turning tangent, no slots, no statistics, no hooks, no diagnostics.
//
// Both start from the same settled state; each round times the engine and the
// specialised loop over the same number of steps and the best of the rounds
// is kept. Prints particle-steps/s of both and their ratio.
//
//   cmake --build build --target specialised_linear
//   build/specialised_linear [steps=20000] [rounds=3] [settle_steps=60000]
//
// Not a test (timings are noisy on a shared machine): tools/bench/features_cost.sh
// runs it beside features_cost.lua; docs/features_cost.md records the ratios.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <unordered_map>
#include <vector>

#include "engine/simulation.hpp"

using namespace granule;
using V = Eigen::Vector2d;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Law {
  double k_n, zeta, mu, k_t, ratio_damping;
};

// Eq. 3.x-free linear law as LinearSpringDashpot defines it (restitution -> zeta).
Law linear_law(double k_n, double e, double mu) {
  const double l = std::log(e);
  return {k_n, -l / std::sqrt(pi * pi + l * l), mu, 2.0 / 7.0 * k_n, 0.5};
}

// The specialised loop's state: flat arrays, a pair list and a wall list.
struct Specialised {
  std::vector<V> x, v, f;
  std::vector<double> w, torque, r, inv_m, inv_i, m;
  std::vector<Wall<2>> walls;
  Law pp{}, pw{};
  double dt = 0, skin = 0;
  // Pair list: i < j, c_n (2 zeta sqrt(k m*)), tangential spring (scalar along t).
  std::vector<std::uint32_t> pi_, pj_;
  std::vector<double> pair_cn, pair_slip;
  std::vector<std::uint32_t> wp_, ww_;
  std::vector<double> wall_cn, wall_slip;
  std::vector<V> x_rebuild;
  double max_sq = 0;
  CellGrid<2> grid;
  Particles<2> scratch;  // positions and radii for CellGrid
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates;
  std::vector<std::uint32_t> touching;
  std::size_t rebuilds = 0;

  void rebuild() {
    scratch.position = x;
    candidates.clear();
    grid.build(scratch, skin, Periodicity{}, candidates);
    std::unordered_map<std::uint64_t, double> old;
    old.reserve(pi_.size());
    for (std::size_t k = 0; k < pi_.size(); ++k)
      if (pair_slip[k] != 0) old[std::uint64_t(pi_[k]) << 32 | pj_[k]] = pair_slip[k];
    pi_.clear(), pj_.clear(), pair_cn.clear(), pair_slip.clear();
    for (auto [a, b] : candidates) {
      if (a > b) std::swap(a, b);
      pi_.push_back(a), pj_.push_back(b);
      const double m_star = 1.0 / (inv_m[a] + inv_m[b]);
      pair_cn.push_back(2 * pp.zeta * std::sqrt(pp.k_n * m_star));
      auto it = old.find(std::uint64_t(a) << 32 | b);
      pair_slip.push_back(it == old.end() ? 0.0 : it->second);
    }
    std::unordered_map<std::uint64_t, double> old_wall;
    for (std::size_t k = 0; k < wp_.size(); ++k)
      if (wall_slip[k] != 0) old_wall[std::uint64_t(wp_[k]) << 32 | ww_[k]] = wall_slip[k];
    wp_.clear(), ww_.clear(), wall_cn.clear(), wall_slip.clear();
    for (std::uint32_t wi = 0; wi < walls.size(); ++wi)
      for (std::uint32_t i = 0; i < x.size(); ++i) {
        if (walls[wi].clearance(x[i], r[i]) >= skin) continue;
        wp_.push_back(i), ww_.push_back(wi);
        wall_cn.push_back(2 * pw.zeta * std::sqrt(pw.k_n * m[i]));
        auto it = old_wall.find(std::uint64_t(i) << 32 | wi);
        wall_slip.push_back(it == old_wall.end() ? 0.0 : it->second);
      }
    x_rebuild = x;
    max_sq = 0;
    ++rebuilds;
  }

  // The tangential law on the scalar spring s along t: T = k_t s + c_t v_t, |T| <= mu |N|.
  static double tangential(const Law& law, double c_n, double& s, double vt, double normal,
                           double dt) {
    s += vt * dt;
    const double c_t = law.ratio_damping * c_n;
    double t = law.k_t * s + c_t * vt;
    const double limit = law.mu * std::abs(normal);
    if (std::abs(t) > limit) {
      t = t > 0 ? limit : -limit;
      s = (t - c_t * vt) / law.k_t;
    }
    return t;
  }

  // Stage times as the engine counts them (neighbour lists, forces, integration).
  double t_neighbor = 0, t_force = 0, t_integrate = 0;

  void step() {
    auto t0 = std::chrono::steady_clock::now();
    if (max_sq > 0.25 * skin * skin) rebuild();
    auto t1 = std::chrono::steady_clock::now();
    t_neighbor += std::chrono::duration<double>(t1 - t0).count();
    std::fill(f.begin(), f.end(), V::Zero());
    std::fill(torque.begin(), torque.end(), 0.0);
    // Pass 1, branch-free: list the candidates that touch (most do not; the
    // engine does the same). A spring whose pair does not touch is released.
    const std::size_t np = pi_.size();
    touching.resize(np);
    std::size_t count = 0;
    {
      const std::uint32_t* const ia = pi_.data();
      const std::uint32_t* const ja = pj_.data();
      const V* const xp = x.data();
      const double* const rp = r.data();
      double* const slip = pair_slip.data();
      std::uint32_t* const list = touching.data();
      for (std::size_t k = 0; k < np; ++k) {
        const std::uint32_t i = ia[k], j = ja[k];
        const double rs = rp[i] + rp[j];
        const bool touches = (xp[i] - xp[j]).squaredNorm() < rs * rs;
        list[count] = static_cast<std::uint32_t>(k);
        count += touches;
        slip[k] *= touches;
      }
    }
    for (std::size_t c = 0; c < count; ++c) {
      const std::uint32_t k = touching[c];
      const std::uint32_t i = pi_[k], j = pj_[k];
      const V d = x[i] - x[j];
      const double rs = r[i] + r[j];
      const double dist = d.norm();
      const V n = d / dist;
      const V t(-n.y(), n.x());
      const double a = rs - dist;
      const V vr = v[j] - v[i];
      const double vn = vr.dot(n);
      const double vt = vr.dot(t) + r[i] * w[i] + r[j] * w[j];  // Eq. 3.10 along t
      const double c_n = pair_cn[k];
      const double normal = pp.k_n * a + c_n * vn;
      const double tf = tangential(pp, c_n, pair_slip[k], vt, normal, dt);
      const V total = normal * n + tf * t;
      f[i] += total;
      f[j] -= total;
      torque[i] -= (r[i] - 0.5 * a) * tf;  // n x (T t) = T
      torque[j] -= (r[j] - 0.5 * a) * tf;
    }
    const std::size_t nw = wp_.size();
    for (std::size_t k = 0; k < nw; ++k) {
      const std::uint32_t i = wp_[k];
      V n, surface, lever;
      const double a = walls[ww_[k]].contact(x[i], r[i], n, surface, lever);
      if (a <= 0) {
        wall_slip[k] = 0;
        continue;
      }
      const V t(-n.y(), n.x());
      const V vr = surface - v[i];
      const double vn = vr.dot(n);
      const double vt = vr.dot(t) + r[i] * w[i];
      const double c_n = wall_cn[k];
      const double normal = pw.k_n * a + c_n * vn;
      const double tf = tangential(pw, c_n, wall_slip[k], vt, normal, dt);
      f[i] += normal * n + tf * t;
      torque[i] -= (r[i] - a) * tf;
    }
    auto t2 = std::chrono::steady_clock::now();
    t_force += std::chrono::duration<double>(t2 - t1).count();
    // Plain pointers: through the vectors, every store might move their data
    // pointers as far as the compiler knows, and it reloads them per particle.
    const std::size_t n = x.size();
    V* const xp = x.data();
    V* const vp = v.data();
    double* const wp = w.data();
    const V* const fp = f.data();
    const double* const tp = torque.data();
    const double* const im = inv_m.data();
    const double* const ii = inv_i.data();
    const V* const x0 = x_rebuild.data();
    const double h = dt;
    double ms = max_sq;
    for (std::size_t i = 0; i < n; ++i) {
      vp[i] += fp[i] * (im[i] * h);  // Eq. 4.8
      xp[i] += vp[i] * h;            // Eq. 4.9
      wp[i] += tp[i] * (ii[i] * h);
      ms = std::max(ms, (xp[i] - x0[i]).squaredNorm());
    }
    max_sq = ms;
    t_integrate += seconds_since(t2);
  }

  double kinetic() const {
    double e = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      e += 0.5 * m[i] * v[i].squaredNorm() + 0.5 / inv_i[i] * w[i] * w[i];
    return e;
  }
};

}  // namespace

int main(int argc, char** argv) {
  const long steps = argc > 1 ? std::atol(argv[1]) : 20000;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
  const long settle = argc > 3 ? std::atol(argv[3]) : 60000;
  const double k_n = 2e4, e = 0.85, mu_pp = 0.4, mu_pw = 0.5;

  Simulation<2> sim;
  sim.set_threads(1);
  sim.add_material({"powder", 1200});
  sim.add_material({"steel", 7800});
  sim.set_contact("powder", "powder", "linear",
                  {{"k_normal", k_n}, {"restitution", e}, {"friction", mu_pp}});
  sim.set_contact("powder", "steel", "linear",
                  {{"k_normal", k_n}, {"restitution", e}, {"friction", mu_pw}});
  WallSpec chamber;
  chamber.name = "chamber";
  chamber.type = WallType::cylinder;
  chamber.material = 1;
  chamber.radius = 12.5e-3;
  chamber.inside = true;
  chamber.angular_velocity = 2000 * 2 * pi / 60;
  sim.add_wall(chamber);
  WallSpec inner = chamber;
  inner.name = "inner";
  inner.center = {5.9e-3, 0, 0};
  inner.radius = 5e-3;
  inner.inside = false;
  inner.angular_velocity = 0;
  sim.add_wall(inner);
  FillSpec fill;
  fill.shape = RegionShape::ball;
  fill.radius = 12.5e-3;
  fill.count = 1500;
  fill.radii = {0.2e-3};
  fill.material = 0;
  fill.seed = 1;
  fill.max_speed = 0.01;
  sim.fill(fill);  // overlapping, as SPEC 2 fills the chamber: the powder flies, then flows
  sim.advance(settle);
  const auto& p = sim.particles();
  const double dt = sim.time_step();

  double best_engine = 1e300, best_special = 1e300;
  SimulationBase::StageTimes engine_stages{}, special_stages{};
  double ke_engine = 0, ke_special = 0;
  std::size_t contacts = 0;
  for (int round = 0; round < rounds; ++round) {
    // The specialised loop starts from the engine's state (tangential springs empty).
    Specialised s;
    s.x = p.position, s.v = p.velocity, s.w = p.spin, s.r = p.radius;
    s.inv_m = p.inv_mass, s.inv_i = p.inv_inertia, s.m = p.mass;
    s.f.assign(s.x.size(), V::Zero());
    s.torque.assign(s.x.size(), 0.0);
    s.walls = sim.walls();
    s.pp = linear_law(k_n, e, mu_pp);
    s.pw = linear_law(k_n, e, mu_pw);
    s.dt = dt;
    s.skin = sim.skin();
    s.scratch = p;
    s.rebuild();
    auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < steps; ++k) s.step();
    const double special = seconds_since(t0);
    if (special < best_special) {
      best_special = special;
      special_stages.neighbor = s.t_neighbor;
      special_stages.force = s.t_force;
      special_stages.integrate = s.t_integrate;
    }
    ke_special = s.kinetic();

    const SimulationBase::StageTimes before = sim.stage_times();
    t0 = std::chrono::steady_clock::now();
    sim.advance(steps);
    const double engine = seconds_since(t0);
    if (engine < best_engine) {
      best_engine = engine;
      const SimulationBase::StageTimes& after = sim.stage_times();
      engine_stages.neighbor = after.neighbor - before.neighbor;
      engine_stages.force = after.force - before.force;
      engine_stages.integrate = after.integrate - before.integrate;
    }
    ke_engine = sim.stats().kinetic_translational + sim.stats().kinetic_rotational;
    contacts = static_cast<std::size_t>(sim.stats().contacts_particle + sim.stats().contacts_wall);
  }
  const double n = static_cast<double>(p.size()) * static_cast<double>(steps);
  fmt::print(
      "scene: 2D Mechanofusion base case, {} particles, linear contacts, {} contacts, dt {:.4g} "
      "s\n",
      p.size(), contacts, dt);
  fmt::print("engine       {:.4g} particle-steps/s ({:.3f} s for {} steps, best of {})\n",
             n / best_engine, best_engine, steps, rounds);
  fmt::print("specialised  {:.4g} particle-steps/s ({:.3f} s)\n", n / best_special, best_special);
  fmt::print("engine / specialised speed: {:.3f}\n", best_special / best_engine);
  const double us = 1e6 / static_cast<double>(steps);
  fmt::print("per step [us]   neighbour lists   forces   integration\n");
  fmt::print("engine          {:15.2f} {:8.2f} {:13.2f}\n", engine_stages.neighbor * us,
             engine_stages.force * us, engine_stages.integrate * us);
  fmt::print("specialised     {:15.2f} {:8.2f} {:13.2f}\n", special_stages.neighbor * us,
             special_stages.force * us, special_stages.integrate * us);
  fmt::print("kinetic energy after the last round: engine {:.4g} J, specialised {:.4g} J\n",
             ke_engine, ke_special);
  return 0;
}
