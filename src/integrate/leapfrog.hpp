// Leap-frog integration of the particles (Eqs. 4.8-4.9), in parallel over
// particles: a = F/m and dw/dt = M/I (SPEC 2: Eq. 4.7's minus sign belongs to
// its force convention), the body forces (gravity, the centripetal field)
// added first, then the damping a scene asked for (fields/damping.hpp). One loop
// per combination of the effects in use (body force, damping, periodic axis,
// spins, fixed particles), so a scene pays in the particle loop only for what it
// has: the branches are resolved when the loop is compiled.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "core/hot_array.hpp"
#include "core/particles.hpp"
#include "fields/body_forces.hpp"
#include "fields/damping.hpp"
#include "neighbor/cell_grid.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace granule {

template <int D>
struct LeapfrogStep {
  Particles<D>& particles;
  const HotArray<Vec<D>>& position_at_rebuild;  // for the displacement since the lists
  const BodyForces<D>& body;
  const Damping& damping;
  Periodicity periodic;  // positions are wrapped back into the box
  double dt;
  // The velocities' kick: dt, or (dt_before + dt) / 2 on the first step after the
  // step changed, since they are held half of the step before behind the
  // positions and must come out half of this one behind.
  double kick;
  bool spins;      // integrate spins (a torque can act: friction, rolling, bonds; spin damping)
  bool any_fixed;  // fixed particles: moved only at a velocity the scene set
  bool parallel;   // ThreadPolicy::particles_parallel
  int threads;
};

// What the step found, folded into the values given.
struct LeapfrogResult {
  double max_displacement_sq = 0;  // m^2, the largest since the lists were built
  double fastest_speed_sq = 0;     // (m/s)^2, this step's fastest particle
  // The first particle whose new state is not finite (left at its last
  // finite state), or the largest int64 for none.
  std::int64_t first_non_finite = std::numeric_limits<std::int64_t>::max();
};

template <int D>
void leapfrog(const LeapfrogStep<D>& step, LeapfrogResult& result) {
  using V = Vec<D>;
  using S = Spin<D>;
  Particles<D>& p = step.particles;
  const BodyForces<D>& body_forces = step.body;
  const std::int64_t n = static_cast<std::int64_t>(p.size());
  const double dt = step.dt;
  const bool body = body_forces.active();
  const bool damped = step.damping.active();
  const DampingStep damping(step.damping, step.kick);
  const bool periodic = step.periodic.on();
  const bool spins = step.spins;
  double max_sq = result.max_displacement_sq;
  double speed_sq = result.fastest_speed_sq;
  std::int64_t bad = result.first_non_finite;
  const int threads = step.threads;
  const Periodicity pbc = step.periodic;
  const bool any_fixed = step.any_fixed;
  auto range = [&](auto body_c, auto damped_c, auto periodic_c, auto spins_c, auto fixed_c,
                   std::int64_t begin, std::int64_t end, double& max_sq_out, double& speed_sq_out,
                   std::int64_t& bad_out) {
    constexpr bool Body = decltype(body_c)::value, Damped = decltype(damped_c)::value;
    constexpr bool Periodic = decltype(periodic_c)::value;
    constexpr bool Spins = decltype(spins_c)::value, Fixed = decltype(fixed_c)::value;
    // The arrays as local pointers: captured by reference they would be
    // reloaded after every store (Eigen's packet stores may alias anything).
    V* const x = p.position.data();
    V* const v = p.velocity.data();
    S* const w = p.spin.data();
    ForceTorque<D>* const load = p.force_torque.data();
    const V* const x_rebuild = step.position_at_rebuild.data();
    const double* const mass = p.mass.data();
    const double* const inv_mass = p.inv_mass.data();
    const double* const inv_inertia = p.inv_inertia.data();
    const std::uint8_t* const fixed = p.fixed.data();
    const BodyForces<D>& forces = body_forces;
    const DampingStep damp = damping;
    // Cundall's local damping, component by component (a spin in 2D is one double).
    auto damp_local = [&damp](auto& a, const auto& v_mid) {
      if constexpr (std::is_same_v<std::decay_t<decltype(a)>, double>)
        a *= damp.local_factor(a, v_mid);
      else
        for (int k = 0; k < a.size(); ++k) a[k] *= damp.local_factor(a[k], v_mid[k]);
    };
    const double h = dt, kick = step.kick;
    const Periodicity periodicity = pbc;
    double max_moved = max_sq_out, fastest = speed_sq_out;
    std::int64_t first_bad = bad_out;
    for (std::int64_t i = begin; i < end; ++i) {
      // The new state in registers first: a step that makes it non-finite is
      // not stored, so the failure report writes the last finite state.
      V v_new;
      S w_new{};
      if (Fixed && fixed[i]) {
        // Forces do not move a fixed particle (its contact force stays for
        // reports): it moves only at the velocity the scene set (prescribed
        // motion, as LAMMPS's fix move linear), its spin as set. A ghost
        // (another flag) follows its owner; one at rest stays put, bit for bit.
        if (fixed[i] != Particles<D>::fixed_flag || v[i] == V::Zero()) continue;
        v_new = v[i];
        if constexpr (Spins) w_new = w[i];
      } else {
        if constexpr (Body) load[i].force += forces.force(mass[i], x[i]);
        if (Damped && damp.translation) {
          V a = load[i].force * inv_mass[i];
          if (damp.local != 0) damp_local(a, V(v[i] + a * (0.5 * kick)));
          v_new = v[i] * damp.keep_v + a * damp.by_v;  // Eq. 4.8 with -c v, exact over the step
        } else {
          v_new = v[i] + load[i].force * (inv_mass[i] * kick);  // Eq. 4.8
        }
        if constexpr (Spins) {
          if (Damped && damp.rotation) {
            S alpha = load[i].torque * inv_inertia[i];
            if (damp.local != 0) damp_local(alpha, S(w[i] + alpha * (0.5 * kick)));
            w_new = w[i] * damp.keep_w + alpha * damp.by_w;
          } else {
            w_new = w[i] + load[i].torque * (inv_inertia[i] * kick);  // no friction: no torque
          }
        }
      }
      V x_new = v_new * h + x[i];  // Eq. 4.9
      V moved_by = x_new - x_rebuild[i];
      if constexpr (Periodic) {
        double& coordinate = x_new[periodicity.axis];
        coordinate -=
            periodicity.length * std::floor((coordinate - periodicity.origin) / periodicity.length);
        moved_by[periodicity.axis] = periodicity.wrap(moved_by[periodicity.axis]);
      }
      const double moved = moved_by.squaredNorm();
      if (!(moved <= max_moved)) {  // also true for NaN
        if (!std::isfinite(moved) || (Spins && !std::isfinite(Dim<D>::spin_sq(w_new)))) {
          if (i < first_bad) first_bad = i;
          continue;
        }
        max_moved = moved;
      }
      fastest = std::max(fastest, v_new.squaredNorm());  // this step moves i by |v_new| dt
      v[i] = v_new;
      x[i] = x_new;
      if constexpr (Spins) w[i] = w_new;
    }
    max_sq_out = max_moved;
    speed_sq_out = fastest;
    bad_out = first_bad;
  };
  auto run = [&](auto body_c, auto damped_c, auto periodic_c, auto spins_c, auto fixed_c) {
    if (step.parallel) {
#pragma omp parallel num_threads(threads) reduction(max : max_sq, speed_sq) reduction(min : bad)
      {
        const std::int64_t t = omp_get_thread_num(), nt = omp_get_num_threads();
        range(body_c, damped_c, periodic_c, spins_c, fixed_c, n * t / nt, n * (t + 1) / nt, max_sq,
              speed_sq, bad);
      }
    } else {
      range(body_c, damped_c, periodic_c, spins_c, fixed_c, 0, n, max_sq, speed_sq, bad);
    }
  };
  using yes = std::true_type;
  using no = std::false_type;
  auto with_fixed = [&](auto b, auto d, auto p, auto s) {
    any_fixed ? run(b, d, p, s, yes{}) : run(b, d, p, s, no{});
  };
  auto with_spins = [&](auto b, auto d, auto p) {
    spins ? with_fixed(b, d, p, yes{}) : with_fixed(b, d, p, no{});
  };
  auto with_periodic = [&](auto b, auto d) {
    periodic ? with_spins(b, d, yes{}) : with_spins(b, d, no{});
  };
  auto with_damping = [&](auto b) { damped ? with_periodic(b, yes{}) : with_periodic(b, no{}); };
  body ? with_damping(yes{}) : with_damping(no{});
  result.max_displacement_sq = max_sq;
  result.fastest_speed_sq = speed_sq;
  result.first_non_finite = bad;
}

}  // namespace granule
