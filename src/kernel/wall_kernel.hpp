// The wall kernel: one step of the contact forces between particles and the
// walls, for one contact model, over its bucket (buckets.hpp). Candidates are
// particle-major, so a team of threads owns whole particles: each particle's
// wall contacts are added to it in slot order, after all pair contacts, as on
// one thread. The reactions on the walls (the inner-piece force of 4.4.1) are
// summed at once on one thread ("fused"); on more, each contact leaves its
// part in its thread's list and scatter_reactions() sums them in slot order.
// For a model with force_batch in this dimension (contact_batch.hpp) the
// contacts go through the law in batches of lanes (wall_batch.hpp), as the
// pair kernel's do.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_state.hpp"
#include "contact/rolling.hpp"
#include "core/particles.hpp"
#include "geometry/walls.hpp"
#include "hooks/contact_log.hpp"
#include "kernel/buckets.hpp"
#include "kernel/team.hpp"
#include "kernel/wall_batch.hpp"

namespace granule {

// What the wall kernel reads and writes of the engine in one step.
template <int D>
struct WallStep {
  Particles<D>& particles;      // reads the state, adds to force_torque
  std::vector<Wall<D>>& walls;  // the reactions, when fused
  double dt;
  std::uint8_t* in_contact;  // the bucket's per-slot flags (0: history cleared)
  ContactLog<D>* log;        // the contact log on a step that records one, else null
  int team;                  // threads (ThreadPolicy::wall_team)
  bool fused;                // reactions summed at once (one thread)
  bool batched;              // the batched force pass where the model has one
};

struct WallTally {
  std::int64_t touching = 0;
  std::int64_t batched = 0;  // of which by the batched pass
  double max_ratio = 0;      // deepest overlap / radius
};

template <int D, typename M>
struct WallKernel {
  // Writes the contact log where step.log is set.
  static void run(WallBucket<D, M>& b, const std::vector<typename M::Params>& params,
                  const WallStep<D>& step, WallTally& tally);

  // The reactions the threads left in their lists, onto the walls in slot
  // order (within a bucket the threads' lists follow one another in
  // increasing k): the order one thread adds them in, so the sums are
  // bit-identical whatever the threads.
  static void scatter_reactions(const WallBucket<D, M>& b, std::vector<Wall<D>>& walls) {
    for (const auto& list : b.touched)
      for (std::size_t e = 0; e < list.count; ++e) {
        Wall<D>& w = walls[list.b[e]];
        w.force -= list.force[e];
        w.axial_torque -= list.axial[e];
      }
  }

 private:
  // The particles ahead (the candidates name particles in memory order, but
  // sparsely: those near a wall).
  static constexpr std::int64_t wall_prefetch_distance = 8;
  static constexpr std::int64_t wall_prefetch_min_candidates = 1 << 13;
};

template <int D, typename M>
void WallKernel<D, M>::run(WallBucket<D, M>& b, const std::vector<typename M::Params>& params,
                           const WallStep<D>& step, WallTally& tally) {
  using History = typename M::template History<D>;
  using V = Vec<D>;
  using S = Spin<D>;
  // Contacts through the law's batch (wall_batch.hpp) where it has one; the
  // rolling variants' torque needs each contact's own state.
  constexpr bool batchable = has_force_batch<M, D>::value && !has_rolling<M>::value;
  const std::int64_t count = static_cast<std::int64_t>(b.size());
  const std::size_t offset = b.offset;
  std::int64_t touching = 0;
  double max_ratio = 0;
  const int team = step.team;
  Particles<D>& p = step.particles;
  ContactLog<D>* const log = step.log;
  b.touched.resize(team);
  // OpenMP may run fewer threads than asked for (see PairKernel::run): the ranges
  // are taken from the team it gives, and the lists of the others stay empty.
  for (auto& list : b.touched) list.count = 0;
  // The work of thread t of nt, called directly on one thread and from an
  // OpenMP region on more. Its arrays are local pointers declared inside:
  // captured by reference, or shared with an OpenMP region, they would be
  // reloaded after every store (Eigen's packet stores may alias anything).
  auto work = [&](std::int64_t t, std::int64_t nt, std::int64_t& touching_out,
                  double& max_ratio_out) {
    // Local pointers: captured by reference they would be reloaded per contact.
    const std::uint32_t* const bp = b.particle.data();
    const std::uint32_t* const bw = b.wall.data();
    const std::uint32_t* const bslot = b.slot.data();
    History* const hist = b.history.data();
    const WallTouch<D>* const touch = b.touch.data();
    const typename M::Params* const par_of = params.data();
    const Wall<D>* const walls = step.walls.data();
    Wall<D>* const reacting_walls = step.walls.data();
    const V* const x = p.position.data();
    const V* const v = p.velocity.data();
    const S* const w_spin = p.spin.data();
    const double* const radius = p.radius.data();
    const double* const mass = p.mass.data();
    const double* const inv_mass = p.inv_mass.data();
    std::uint8_t* const in_contact = step.in_contact;
    const bool fused = step.fused;
    ForceTorque<D>* const load = p.force_torque.data();
    const double dt = step.dt;
    std::int64_t touching = 0;
    double max_ratio = 0;
    // Threads own whole particles (the candidates are particle-major): a range
    // ends where a particle's run of candidates does. Each particle's wall
    // contacts are added to it in slot order, after all pair contacts, as on
    // one thread; the reactions on the walls are summed afterwards in slot
    // order (scatter_forces) from what each contact leaves in the list.
    // cut() never moves a point backwards, so the ranges never overlap.
    auto cut = [&](std::int64_t at) {
      while (at > 0 && at < count && bp[at] == bp[at - 1]) ++at;
      return at;
    };
    const std::int64_t begin = cut(count * t / nt), end = cut(count * (t + 1) / nt);
    StepList<D>& list = b.touched[t];
    list.start(static_cast<std::size_t>(end - begin));
    if (!fused) list.reserve_outputs(static_cast<std::size_t>(end - begin));
    std::uint32_t* const out_b = list.b.data();
    V* const out_force = list.force.data();
    double* const out_axial = list.axial.data();
    const bool prefetch = count >= wall_prefetch_min_candidates;
    // A touching candidate's geometry, and its place in this thread's list.
    struct Found {
      V n, surface_velocity, lever;
      double overlap;
      double r_star;  // R*, only for a law that reads it (contact_state.hpp)
      std::size_t e;
    };
    // Candidate k's geometry, from the wall (or, for a mesh, as
    // resolve_mesh_contacts found it this step); false when it does not touch
    // (its history cleared if it did), else it is listed.
    auto find = [&](std::int64_t k, Found & f) __attribute__((always_inline)) {
      const std::uint32_t i = bp[k];
      const Wall<D>& w = walls[bw[k]];
      // R* from the contact's own closest point (a mesh's faces count as flat,
      // a polyline's arcs as circles).
      f.r_star = std::numeric_limits<double>::quiet_NaN();
      // A law that touches only at overlap > 0 skips the geometry of a
      // candidate surely clear of its cylinder (about half of them in a drum).
      const bool apart = !M::adhesive && w.surely_apart(x[i], radius[i]);
      if (!apart && is_surface_wall(w.type)) {  // found this step by resolve_mesh_contacts
        const WallTouch<D>& t = touch[k];
        f.n = t.normal, f.surface_velocity = t.surface_velocity, f.lever = t.lever;
        f.overlap = t.overlap;
        f.r_star = t.effective_radius;
      } else if (!apart) {
        f.overlap = w.contact(x[i], radius[i], f.n, f.surface_velocity, f.lever,
                              uses_effective_radius<M>::value ? &f.r_star : nullptr);
      }
      if (apart || !M::touching(par_of[bslot[k]], hist[k], f.overlap)) {
        if (in_contact[k]) {
          hist[k] = History{};
          in_contact[k] = 0;
        }
        return false;
      }
      in_contact[k] = 1;
      f.e = list.count;  // this contact's place in the list
      list.push(static_cast<std::uint32_t>(k) << 1 | 1u);
      return true;
    };
    // take(k, particle, found) for each candidate of this thread's range that
    // touches, in slot order, with the particles' data fetched ahead.
    auto each_touching = [&](auto&& take) __attribute__((always_inline)) {
      for (std::int64_t k = begin; k < end; ++k) {
        if (prefetch && k + wall_prefetch_distance < end) {
          const std::uint32_t ahead = bp[k + wall_prefetch_distance];
          __builtin_prefetch(&x[ahead]);
          __builtin_prefetch(&radius[ahead]);
          __builtin_prefetch(&v[ahead]);
          __builtin_prefetch(&w_spin[ahead]);
          __builtin_prefetch(&load[ahead], 1);
        }
        Found f;
        if (find(k, f)) take(k, bp[k], f);
      }
    };
    // Contact k's results, both passes alike: the force and torque onto
    // particle i, the reaction onto its wall (at once, or left in the list at
    // place e for scatter_reactions), the deepest overlap so far (`worst`: a
    // local of the caller's, so that it stays in a register), the log.
    auto apply = [&](std::int64_t k, std::uint32_t i, std::uint32_t wall, std::size_t e, double r,
                     const V& total, const S& torque, double axial, double overlap, const V& n,
                     double normal_force, double normal_velocity, const V& tangential_force,
                     double& worst) __attribute__((always_inline)) {
      load[i].force += total;
      load[i].torque += torque;
      if (fused) {
        Wall<D>& reacting = reacting_walls[wall];
        reacting.force -= total;
        reacting.axial_torque -= axial;
      } else {
        out_b[e] = wall;
        out_force[e] = total;
        out_axial[e] = axial;
      }
      if (overlap > worst * r) worst = overlap / r;
      if (log) {  // at run time, as the pair kernel's per-contact pass (pair_kernel.hpp)
        log->record(offset + k, static_cast<std::int32_t>(i), -1 - static_cast<std::int32_t>(wall),
                    overlap, normal_force, normal_velocity, n, tangential_force,
                    x[i] - (r - overlap) * n);
      }
    };
    if constexpr (batchable) {
      if (step.batched) {
        // The contacts' geometry found one by one, their laws computed lane by
        // lane (wall_batch.hpp), the results added in slot order.
        WallBatch<D, M> batch;
        batch.c.dt = dt;
        auto flush = [&]() {
          batch.pad();
          batch.kinematics();
          M::force_batch(batch.params, batch.history, batch.c);
          batch.totals();
          double worst = max_ratio;
          for (int l = 0; l < batch.count; ++l) {
            const std::uint32_t k = batch.k[l], i = batch.i[l], wall = batch.wall[l];
            batch.history.store(l, hist[k]);
            const V total = batch.total(l);
            apply(k, i, wall, batch.entry[l], batch.r[l], total, batch.torque(l),
                  walls[wall].axial_moment(batch.lever(l), total), batch.c.overlap[l],
                  batch.normal(l), batch.c.normal_force[l], batch.c.normal_velocity[l],
                  batch.tangential_force(l), worst);
          }
          max_ratio = worst;
          touching += batch.count;
          batch.count = 0;
        };
        each_touching([&](std::int64_t k, std::uint32_t i, const Found& f) {
          const int l = batch.count++;
          batch.k[l] = static_cast<std::uint32_t>(k), batch.i[l] = i, batch.wall[l] = bw[k];
          batch.entry[l] = static_cast<std::uint32_t>(f.e);
          batch.params[l] = &par_of[bslot[k]];
          // The mass only where the law reads it this step (batch_needs_mass,
          // contact_batch.hpp): a line the batch would otherwise miss on.
          const History& h = hist[k];
          batch.gather_lane(l, f.n, f.overlap, f.surface_velocity, v[i], w_spin[i], radius[i],
                            batch_needs_mass<M>(h) ? inv_mass[i] : 1.0, f.r_star, f.lever, h);
          if (batch.count == batch.lanes) flush();
        });
        if (batch.count) flush();
        touching_out += touching;
        if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
        return;
      }
    }
    each_touching([&](std::int64_t k, std::uint32_t i, const Found& found) {
      const V& n = found.n;
      const double overlap = found.overlap;
      const Wall<D>& w = walls[bw[k]];
      const typename M::Params& par = par_of[bslot[k]];
      History& h = hist[k];
      ContactState<D> c;
      c.dt = dt;
      c.normal = n;
      c.overlap = overlap;
      const V v_rel = found.surface_velocity - v[i];
      c.normal_velocity = v_rel.dot(n);
      // At the wall's surface, where the torque below applies the force (lever
      // r - a): the work the contact takes is the work the particle gives.
      const double lever = radius[i] - overlap;
      c.tangential_velocity =
          v_rel - n * c.normal_velocity + lever * Dim<D>::spin_cross(w_spin[i], n);
      c.effective_mass = mass[i];
      c.inv_mass_sum = inv_mass[i];
      const double r = radius[i];
      c.effective_radius = found.r_star;
      const ContactForce<D> f = M::force(par, h, c);
      const V total = f.normal * n + f.tangential;
      S torque_i = Dim<D>::torque(-lever * n, f.tangential);  // at the wall surface
      double axial = w.axial_moment(found.lever, total);
      if constexpr (has_rolling<M>::value) {
        // Rolling resistance (rolling.hpp) against the wall's own spin: M on
        // the particle, -M on the wall (its axial part joins the reaction).
        S wall_spin;
        if constexpr (D == 3)
          wall_spin = w.axis * w.angular_velocity;
        else
          wall_spin = w.angular_velocity;
        const double inertia =
            rolling_inertia(rolling_compliance(inv_mass[i], p.inv_inertia[i], r), 0.0);
        const S roll = M::rolling_torque(par, h, c, f.normal, S(w_spin[i] - wall_spin), inertia,
                                         p.inv_inertia[i]);
        torque_i += roll;
        if constexpr (D == 3)
          axial += w.axis.dot(roll);
        else
          axial += roll;
      }
      apply(k, i, bw[k], found.e, r, total, torque_i, axial, overlap, n, f.normal,
            c.normal_velocity, f.tangential, max_ratio);
      ++touching;
    });
    touching_out += touching;
    if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
  };
  run_on_team(team, work, touching, max_ratio);
  tally.touching += touching;
  if (batchable && step.batched) tally.batched += touching;
  if (max_ratio > tally.max_ratio) tally.max_ratio = max_ratio;
}

}  // namespace granule
