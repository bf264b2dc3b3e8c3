#include "engine/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <type_traits>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/errors.hpp"
#include "core/random.hpp"
#include "integrate/leapfrog.hpp"
#include "kernel/pair_kernel.hpp"
#include "kernel/team.hpp"
#include "kernel/wall_kernel.hpp"
#include "neighbor/contact_lists.hpp"

namespace granule {

namespace {
using Clock = std::chrono::steady_clock;
// Scenes this large are kept in space-filling-curve order (their data no longer
// fits in the fast caches, so neighbours in memory matter).
constexpr std::size_t sort_min_particles = 4096;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

// ----------------------------------------------------------------------------
// The step. Stages in order; each is timed so the REPL can show where time goes.
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::step() {
  if (!moved_bond_gaps_.empty()) settle_moved_bonds();  // sim:set_position's, before the forces
  // A callback that changed what the time step and the lists depend on (a law's
  // parameters, particles added) is prepared for at the very next step, not at
  // the next chunk of steps, whose length follows the wall clock: the same scene
  // gives the same bits however fast the machine runs it. (A spread run
  // prepares the gathered scene before it shares it again.)
  if (!prepared_ && !external_rebuilds_) prepare();
  auto t0 = Clock::now();
  // 1. Neighbour lists: rebuilt only when something moved more than half the skin.
  // Large scenes are re-sorted along a space-filling curve every 32nd rebuild.
  if (!external_rebuilds_ && (!lists_valid_ || lists_stale())) {
    if (p_.size() >= sort_min_particles && rebuilds_ % 32 == 0)
      sort_particles();
    else
      rebuild_lists();
  }
  if (ongoing_marks_due_) mark_ongoing_contacts();
  // Whether deep overlaps are still the scene's own, as the step begins: the pairs'
  // check below may end that grace within this step on one process, where a spread
  // run learns it from every rank at the next step's start; the wall check reads
  // this, the same on both.
  const bool overlaps_the_scenes = scene_overlaps_;
  auto t1 = Clock::now();
  stage_times_.neighbor += std::chrono::duration<double>(t1 - t0).count();

  // 2. Contact forces: one inlined kernel per contact model, each contact
  // writing its own slot. The contact log is filled only on steps where the
  // scene records contacts or an attached diagnostic needs them.
  bool observed = record_contacts_ || tracking_;
  for (const auto& d : diagnostics_)
    if (d.needs.contacts && step_ % d.every == 0 && d.diagnostic->sampling().due(time_, dt_))
      observed = true;
  if (observed) {
    log_.resize(slot_count_);
    log_.model_at = slot_models();  // what contacts() names each slot's model by
  }
  log_.filled = observed;
  gathered_contacts_.reset();
  removed_from_gathered_.clear();
  // Every thread count adds the contacts to each particle in slot order (pairs
  // model by model, then walls), so the result is bit-identical whatever the
  // number of threads. Pair contacts add their forces at once (PairKernel
  // defers those of the particles two threads share); so do wall contacts, each
  // thread owning whole particles (WallKernel). The reactions on the walls
  // are summed at once on one thread ("fused"); on more each contact leaves
  // its part in its list and scatter_forces() sums them in slot order. A scene
  // whose candidates are all below the parallel threshold runs every contact
  // loop on one thread.
  const ThreadPolicy policy = thread_policy();
  fused_ = !keep_wall_reactions_ && policy.fused(static_cast<std::int64_t>(slot_count_));
  zero_forces();
  for (auto& w : walls_) w.force.setZero(), w.axial_torque = 0;
  // Pruned pair lists are noted afresh once two particles may have closed the
  // prune distance between them, or when another rank notes its own.
  prune_due_ = prune_with_others_ || prune_distance_closed();
  prune_with_others_ = false;
  if (prune_due_) {
    if (pruning_) tune_prune_distance();
    prune_travel_ = 0;
  }
  PairTally pairs;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& pb = std::get<I>(pair_buckets_);
    if (!pb.size()) return;
    auto& kernel = std::get<I>(pair_kernels_);
    const PairStep<D> at{p_,
                         dt_,
                         periodic_,
                         slot_in_contact_.data() + pb.offset,
                         observed ? &log_ : nullptr,
                         policy.pair_team(static_cast<std::int64_t>(pb.size())),
                         batched_contacts_,
                         pruning_,
                         prune_due_,
                         prune_distance()};
    if (observed)
      kernel.template run<true>(pb, pairs_.params<I>(), at, pairs);
    else
      kernel.template run<false>(pb, pairs_.params<I>(), at, pairs);
  });
  contacts_particle_ = pairs.touching;
  contacts_batched_ = pairs.batched;
  candidates_visited_ = pairs.visited;
  prune_cycle_visited_ += pairs.visited;
  ++prune_cycle_steps_;
  prunes_ += pairs.prunes;
  rebalances_ += pairs.rebalances;
  stage_times_.scatter += pairs.scatter_seconds;
  stage_times_.pair_wait += pairs.wait_seconds;
  // The pairs' deepest overlap / smaller radius, before the walls add theirs.
  const double pair_overlap_ratio = pairs.max_ratio;
  const auto walls_start = Clock::now();
  if (!meshes_.empty()) resolve_meshes();  // mesh walls' contacts, for the wall kernels
  if (mesh_marks_due_) mark_ongoing_mesh_contacts();
  WallTally wall_tally;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    auto& wb = std::get<I>(wall_buckets_);
    if (!wb.size()) return;
    const WallStep<D> at{p_,
                         walls_,
                         dt_,
                         slot_in_contact_.data() + wb.offset,
                         observed ? &log_ : nullptr,
                         policy.wall_team(static_cast<std::int64_t>(wb.size()), fused_),
                         fused_,
                         batched_contacts_};
    WallKernel<D, M>::run(wb, pairs_.params<I>(), at, wall_tally);
  });
  contacts_wall_ = wall_tally.touching;
  contacts_wall_batched_ = wall_tally.batched;
  max_overlap_ratio_ = std::max(pair_overlap_ratio, wall_tally.max_ratio);
  if ((pair_overlap_ratio > deep_checked_pair_ || wall_tally.max_ratio > deep_checked_wall_ ||
       (deep_rescan_step_ >= 0 && step_ >= deep_rescan_step_)) &&
      !deep_modes_.empty())
    check_deep_contact_modes(pair_overlap_ratio, wall_tally.max_ratio);
  // (Not while the scene's own overlaps relax: an overlapping fill throws its
  // particles at the walls that hard by design, check_overlaps.)
  if (wall_tally.max_ratio > overlap_warning_ && !wall_overlap_warned_ && !scene_overlaps_)
    warn_deep_wall_contact();
  // A centre a radius past a half-space (or half a thin post's radius inside
  // it) has escaped: stopped at once, not at the next list rebuild (which a
  // particle held still never triggers).
  if (wall_tally.max_ratio > 1) check_escapes();
  stage_times_.walls += seconds_since(walls_start);
  // The reactions on the walls (the inner-piece force of 4.4.1), summed in
  // slot order.
  if (!fused_) {
    const auto scatter_start = Clock::now();
    scatter_forces();
    stage_times_.scatter += std::chrono::duration<double>(Clock::now() - scatter_start).count();
  }
  // Parallel bonds (contact/parallel_bond.hpp) act beside the contact laws:
  // their loads added after the contacts' in bond order, on one thread.
  if (bonds_.intact > 0) apply_bonds();  // simulation_bonds.cpp
  bond_moved_with_.clear();
  bonds_unmoved_from_ = bonds_.size();
  if (observed) list_logged_slots();  // simulation_log.cpp
  // One comparison a step; the contacts are looked at only when it fails.
  last_pair_overlap_ratio_ = pair_overlap_ratio;
  // The grace of particles placed mid-run also ends once their own pairs are
  // clear: the deep pairs left are the run's (a distributed run ends it with
  // every rank's verdict, end_placed_grace_with).
  last_placed_pair_ratio_ = INFINITY;
  if (scene_overlaps_ && !grace_for_all_)
    last_placed_pair_ratio_ =
        pair_overlap_ratio > overlap_warning_ ? placed_pairs_deepest() : pair_overlap_ratio;
  if (!external_overlap_grace_) end_placed_grace_with(last_placed_pair_ratio_);
  if (pair_overlap_ratio > overlap_warning_)
    check_overlaps(pair_overlap_ratio);
  else if (!external_overlap_grace_)
    end_overlap_grace();
  // (While the scene's own overlaps relax, as after an overlapping fill, its
  // particles are thrown at the walls that hard by design: check_overlaps.)
  const bool pressed_due = wall_tally.max_ratio > wall_through_ratio;
  const bool thin_deep = wall_tally.max_ratio > thin_watch_ratio;
  if ((pressed_due || thin_deep || thin_deep_last_step_) && !overlaps_the_scenes)
    check_thin_walls(pressed_due, thin_deep || thin_deep_last_step_);  // simulation_checks.cpp
  thin_deep_last_step_ = thin_deep;
  auto t2 = Clock::now();
  stage_times_.force += std::chrono::duration<double>(t2 - t1).count();

  // 3. Diagnostics: contact events, then the observers due this step.
  if (!diagnostics_.empty()) {
    if (tracking_) track_contacts();
    observe(observed);
  }
  auto t3 = Clock::now();
  stage_times_.diagnostics += std::chrono::duration<double>(t3 - t2).count();

  // 4. Body forces and leap-frog (Eqs. 4.8-4.9).
  integrate();
  // The clock moves with the particles before the checks, so that a failing
  // step leaves (for the failure's snapshot, or a scene that catches the error
  // and goes on) positions and time that belong together.
  if (dt_ != clock_dt_) clock_time_ = time_, clock_step_ = step_, clock_dt_ = dt_;
  ++step_;
  time_ = clock_time_ + static_cast<double>(step_ - clock_step_) * dt_;
  if (non_finite_index_ != SIZE_MAX || last_wall_travel_ > smallest_free_radius_ ||
      last_fastest_speed_sq_ * (dt_ * dt_) > smallest_radius_ * smallest_radius_ ||
      periodic_walls_move_) {
    // The wall check reads the walls' velocities of the step just taken, so
    // the schedules move on only after it (and also when it fails).
    try {
      if (non_finite_index_ != SIZE_MAX) report_non_finite(non_finite_index_);
      if (last_fastest_speed_sq_ * (dt_ * dt_) > smallest_radius_ * smallest_radius_)
        report_step_over();
      if (last_wall_travel_ > smallest_free_radius_) report_wall_step_over();
      if (periodic_walls_move_) report_walls_leave_period();
    } catch (...) {
      // The step's failure is the error to report: a schedule that fails to
      // apply now (a ramp refused at its next value) waits for the next step.
      if (!schedules_.empty()) try {
          apply_schedules();
        } catch (...) {
        }
      throw;
    }
  }
  // Schedules (ramps): their targets set to the values of the next step's time.
  if (!schedules_.empty()) apply_schedules();
  auto t4 = Clock::now();
  stage_times_.integrate += std::chrono::duration<double>(t4 - t3).count();

  // 5. Hooks (output, script callbacks): one check when there are none.
  if (!hooks_.empty()) {
    fire_hooks();
    stage_times_.hooks += seconds_since(t4);
  }
}

template <int D>
void Simulation<D>::advance(std::int64_t steps) {
  if (steps < 0)
    throw InputError(fmt::format("cannot advance a negative number of steps ({})", steps));
  if (!prepared_) prepare();
  if (steps > 0 && step_ == 0) fire_start_hooks();
  for (std::int64_t s = 0; s < steps; ++s) step();
}

// ----------------------------------------------------------------------------
// Contact events for observers: a serial pass over the logged slots, so event
// order is the slot order whatever the thread count.
// ----------------------------------------------------------------------------
template <int D>
template <typename Bucket>
void Simulation<D>::track_bucket(Bucket& b) {
  if (b.track.size() != b.size()) b.track.assign(b.size(), ContactTrack<D>{});
  auto identify = [&](std::size_t k, ContactEvent<D>& e) {
    if constexpr (Bucket::is_pair) {
      e.id_a = b.id_i[k];
      e.id_b = b.id_j[k];
      const double ri = p_.radius[b.i[k]], rj = p_.radius[b.j[k]];
      e.effective_radius = ri * rj / (ri + rj);
    } else {
      e.id_a = b.id[k];
      e.wall = static_cast<int>(b.wall[k]);
      e.effective_radius =
          walls_[b.wall[k]].effective_radius(p_.position[b.particle[k]], p_.radius[b.particle[k]]);
    }
  };
  auto visit = [&](std::size_t k) {
    const std::size_t s = b.offset + k;
    ContactTrack<D>& t = b.track[k];
    if (t.begin_time == ContactTrack<D>::ongoing) {
      if (!log_.active[s]) t = ContactTrack<D>{};  // its end: no event either
      return;
    }
    if (log_.active[s]) {
      const double fn = log_.normal_force[s], a = log_.overlap[s];
      if (t.begin_time < 0) {
        t.begin_time = time_;
        t.impact_velocity = log_.overlap_rate[s];
        t.peak_normal_force = fn;
        t.peak_overlap = a;
        t.position = log_.point[s];
        ContactEvent<D> e;
        identify(k, e);
        e.begin_time = time_;
        e.impact_velocity = t.impact_velocity;
        e.position = t.position;
        log_.began.push_back(e);
      } else {
        if (fn > t.peak_normal_force) t.peak_normal_force = fn;
        if (a > t.peak_overlap) t.peak_overlap = a;
      }
    } else if (t.begin_time >= 0) {
      ContactEvent<D> e;
      identify(k, e);
      e.begin_time = t.begin_time;
      e.end_time = time_;
      e.impact_velocity = t.impact_velocity;
      e.peak_normal_force = t.peak_normal_force;
      e.peak_overlap = t.peak_overlap;
      e.position = t.position;
      log_.ended.push_back(e);
      t = ContactTrack<D>{};
    }
  };
  if constexpr (Bucket::is_pair) {
    // Only the contacts the kernel listed (touching now, or until now) can
    // begin, go on or end; the other candidates (~10x more in the Mechanofusion
    // base case) have nothing to track. The lists are in increasing k, so the
    // events come in the same order as from a loop over all of them.
    if (!b.size()) return;
    for (const auto& list : b.touched)
      for (const std::uint32_t entry : list) visit(entry >> 1);
  } else {
    for (std::size_t k = 0; k < b.size(); ++k) visit(k);
  }
}

// The contacts going on when event tracking begins (a diagnostic attached to a bed
// in contact) began before it: marked `ongoing`, they give no events. Told by the
// particles' overlap at the start of the first step after the attach, when the
// lists are built (after particles were added, removed or moved, on every rank of
// a spread run alike): the state alone decides, as on one process, and after a
// restart (the due mark travels in the checkpoint). Pairs and analytic walls here;
// a mesh's or polyline's contacts, found within the step, once that step has found
// them (mark_ongoing_mesh_contacts).
template <int D>
void Simulation<D>::mark_ongoing_contacts() {
  ongoing_marks_due_ = false;
  if (!tracking_) return;
  mesh_marks_due_ = !meshes_.empty();
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& pairs = std::get<I>(pair_buckets_);
    pairs.track.assign(pairs.size(), ContactTrack<D>{});
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const std::uint32_t i = pairs.i[k], j = pairs.j[k];
      const V d = separation(p_.position[i], p_.position[j]);
      const double reach = p_.radius[i] + p_.radius[j];
      if (d.squaredNorm() < reach * reach) pairs.track[k].begin_time = ContactTrack<D>::ongoing;
    }
    auto& walls = std::get<I>(wall_buckets_);
    walls.track.assign(walls.size(), ContactTrack<D>{});
    for (std::size_t k = 0; k < walls.size(); ++k) {
      const std::uint32_t i = walls.particle[k], w = walls.wall[k];
      if (is_surface_wall(walls_[w].type)) continue;
      V n, surface_velocity, lever;
      if (walls_[w].contact(p_.position[i], p_.radius[i], n, surface_velocity, lever) > 0)
        walls.track[k].begin_time = ContactTrack<D>::ongoing;
    }
  });
}

template <int D>
void Simulation<D>::mark_ongoing_mesh_contacts() {
  mesh_marks_due_ = false;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& walls = std::get<I>(wall_buckets_);
    if (walls.track.size() != walls.size()) walls.track.assign(walls.size(), ContactTrack<D>{});
    for (std::size_t k = 0; k < walls.size(); ++k)
      if (is_surface_wall(walls_[walls.wall[k]].type) && walls.touch[k].overlap > 0)
        walls.track[k].begin_time = ContactTrack<D>::ongoing;
  });
}

template <int D>
void Simulation<D>::track_contacts() {
  log_.began.clear();
  log_.ended.clear();
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    track_bucket(std::get<I>(pair_buckets_));
    track_bucket(std::get<I>(wall_buckets_));
  });
}

template <int D>
void Simulation<D>::observe(bool contacts_logged) {
  StepView<D> view{p_, walls_, log_, time_, dt_, step_, body_.active() ? &body_ : nullptr};
  for (auto& d : diagnostics_) {
    if (d.needs.events) d.diagnostic->on_events(view);
    if (step_ % d.every == 0) {
      if (d.needs.contacts && !contacts_logged) continue;  // cannot happen: observed covers it
      d.diagnostic->observe(view);
    }
  }
}

// ----------------------------------------------------------------------------
// Forces per particle: one serial pass over the slots in order. The kernels
// ran in parallel, each contact writing its own slot; summing here in slot
// order makes every particle's total independent of the thread count. The
// pass visits only the contacts the kernels listed (a few hundred in the
// Mechanofusion base case, against ~3000 candidates).
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::zero_forces() {
  ForceTorque<D>* const load = p_.force_torque.data();
  const std::int64_t n = static_cast<std::int64_t>(p_.size());
  const ThreadPolicy policy = thread_policy();
  over_particles(!fused_ && policy.particles_parallel(n), policy.threads, n,
                 [&](std::int64_t lo, std::int64_t hi) {
                   // ForceTorque is doubles alone, and a double of zero bits is 0.0: one
                   // memset rather than a store per member (the pads too, which the
                   // batched pair loop needs at zero).
                   std::memset(static_cast<void*>(load + lo), 0,
                               static_cast<std::size_t>(hi - lo) * sizeof(ForceTorque<D>));
                 });
}

// The reactions on the walls (the inner-piece force of 4.4.1), in slot order
// (model by model): the particles' sides were added by the wall kernels.
template <int D>
void Simulation<D>::scatter_forces() {
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(wall_buckets_);
    if (b.size()) WallKernel<D, ContactModelAt<I>>::scatter_reactions(b, walls_);
  });
}

// ----------------------------------------------------------------------------
// Integration (src/integrate/leapfrog.hpp), then the walls that move.
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::integrate() {
  const ThreadPolicy policy = thread_policy();
  const std::int64_t n = static_cast<std::int64_t>(p_.size());
  // Spins only when a pair in use has friction or a bond is intact; a law changed
  // since prepare() (a friction ramp in a hook) counts as frictional until the next prepare().
  // Bonds carry moments whatever the contact laws are.
  const bool spins = rotation_ || !prepared_ || bonds_.intact > 0 || damping_.spin > 0;
  // clock_dt_ is the step the last one was taken with (0 before the first).
  const double kick = clock_dt_ > 0 && clock_dt_ != dt_ ? (clock_dt_ + dt_) / 2 : dt_;
  const LeapfrogStep<D> at{p_,
                           position_at_rebuild_,
                           body_,
                           damping_,
                           periodic_,
                           dt_,
                           kick,
                           spins,
                           any_fixed_,
                           policy.particles_parallel(n),
                           policy.threads};
  LeapfrogResult result;
  result.max_displacement_sq = max_displacement_sq_;
  leapfrog(at, result);
  max_displacement_sq_ = result.max_displacement_sq;
  // The fastest particle moved at most |v| dt: what pruning needs (PrunedLists).
  prune_travel_ += std::sqrt(result.fastest_speed_sq) * dt_;
  last_fastest_speed_sq_ = result.fastest_speed_sq;
  const std::int64_t bad = result.first_non_finite;
  if (bad != std::numeric_limits<std::int64_t>::max() && non_finite_index_ == SIZE_MAX)
    non_finite_index_ = static_cast<std::size_t>(bad);
  wall_travel_.assign(walls_.size(), 0.0);
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    Wall<D>& wall = walls_[w];
    // Meshes and polylines are moved, and their travel counted, by meshes_.move.
    if (is_surface_wall(wall.type)) continue;
    if (!wall.velocity.isZero()) {  // planes and finite walls translate
      const V step = wall.velocity * dt_;
      wall.point += step;
      wall.center += step;
      wall.moved_since_rebuild += step;
      // An infinite plane steps over nothing moving away or along itself: only its
      // advance towards the particles' side counts. (stableNorm: 1e300 m/s gives no inf.)
      wall_travel_[w] = wall.type == WallType::plane && !wall.bounded
                            ? std::max(0.0, step.dot(wall.normal))
                            : step.stableNorm();
    }
  }
  meshes_.move(walls_, dt_, wall_travel_);
  // (In 2D no wall is checked against the period: check_walls_repeat.)
  if (D == 3 && periodic_.on()) {
    periodic_walls_move_ = false;
    for (const auto& wall : walls_)
      periodic_walls_move_ = periodic_walls_move_ || wall.moves_along(periodic_.axis);
  }
  // Their largest, for step()'s one comparison.
  last_wall_travel_ =
      wall_travel_.empty() ? 0.0 : *std::max_element(wall_travel_.begin(), wall_travel_.end());
}

template <int D>
bool Simulation<D>::lists_stale() const {
  // Two particles closing on each other each move at most half the skin.
  const double half = 0.5 * skin_;
  if (max_displacement_sq_ > half * half) return true;
  double wall_moved = 0;
  for (const auto& w : walls_) wall_moved = std::max(wall_moved, w.moved_since_rebuild.norm());
  return wall_moved > 0 && std::sqrt(max_displacement_sq_) + wall_moved > skin_;
}

// ----------------------------------------------------------------------------
// Neighbour lists (src/neighbor/contact_lists.hpp)
// ----------------------------------------------------------------------------
// The step's contact buffers, from the buckets' sizes and offsets (after a rebuild, or a checkpoint
// is loaded).
template <int D>
void Simulation<D>::build_slots() {
  std::size_t slots = 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    slots = std::max(slots, std::get<I>(pair_buckets_).offset + std::get<I>(pair_buckets_).size());
    slots = std::max(slots, std::get<I>(wall_buckets_).offset + std::get<I>(wall_buckets_).size());
  });
  slot_count_ = slots;
  if (slots >= (std::size_t{1} << 30))
    throw RunError(fmt::format("{} candidate contacts: more than this build supports", slots));
  // Every slot counts as possibly in contact until its first step: one that is
  // not touching then clears the history it may have carried over.
  slot_in_contact_.assign(slots, 1);
}

// At a global prune: the cycle that ends here, if it ran from one global prune
// to the next (not cut short by a list rebuild, whose fresh lists are pruned
// at once), visited so many candidates per step. Worse than the cycle before
// it: the fraction's last move was the wrong way, so it turns. The fraction
// moves by a quarter between 1/32 and 1/4 of the skin. In a slow flow the
// prunes are rare and a near distance pays (the 2D Mechanofusion base case
// visits ~30 % fewer candidates at 1/16 than at 1/4); in a fast one the
// prunes come every few steps and a farther one does (docs/performance.md).
template <int D>
void Simulation<D>::tune_prune_distance() {
  constexpr double nearest = 1.0 / 32, farthest = 0.25, factor = 1.25;
  if (std::isfinite(prune_travel_) && prune_cycle_steps_ > 0) {
    const double cost =
        static_cast<double>(prune_cycle_visited_) / static_cast<double>(prune_cycle_steps_);
    if (prune_cycle_cost_ >= 0 && cost >= prune_cycle_cost_) prune_direction_ = -prune_direction_;
    prune_cycle_cost_ = cost;
    prune_fraction_ *= prune_direction_ < 0 ? 1 / factor : factor;
    if (prune_fraction_ <= nearest) prune_fraction_ = nearest, prune_direction_ = 1;
    if (prune_fraction_ >= farthest) prune_fraction_ = farthest, prune_direction_ = -1;
  }
  prune_cycle_steps_ = prune_cycle_visited_ = 0;
}

template <int D>
void Simulation<D>::rebuild_lists() {
  prune_travel_ = std::numeric_limits<double>::infinity();  // new candidates: prune them all
  any_fixed_ = std::any_of(p_.fixed.begin(), p_.fixed.end(), [](std::uint8_t f) { return f != 0; });
  candidates_.clear();
  grid_.build(p_, skin_, periodic_, candidates_);
  prepare_meshes();

  // Pair slots first (all models), then wall slots; in canonical order the
  // candidates by particle id (contact_lists.hpp).
  const std::vector<std::uint32_t> id_order =
      canonical_order_ ? p_.in_id_order() : std::vector<std::uint32_t>{};
  std::size_t slots = 0;
  // A model no pair of materials uses has nothing to list: its empty bucket
  // is not scanned for (every model's scan reads all candidates).
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& bucket = std::get<I>(pair_buckets_);
    if (bucket.size() || pairs_.uses(I)) {
      const std::size_t old =
          list_pairs(bucket, I, p_, pairs_, candidates_, tracking_, canonical_order_);
      std::get<I>(pair_kernels_).on_new_list(old, bucket.size());
    }
    bucket.offset = slots;
    slots += bucket.size();
  });
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& bucket = std::get<I>(wall_buckets_);
    if (bucket.size() || pairs_.uses(I))
      list_walls(bucket, I, p_, walls_, meshes_, pairs_, skin_, tracking_, id_order);
    bucket.offset = slots;
    slots += bucket.size();
  });
  build_slots();
  check_escapes();  // a particle whose centre passed a wall (simulation_checks.cpp)

  position_at_rebuild_.assign(p_.position.begin(), p_.position.end());
  max_displacement_sq_ = 0;
  for (auto& w : walls_) w.moved_since_rebuild.setZero();
  lists_valid_ = true;
  list_indices_stale_ = false;
  ++rebuilds_;
}

template <int D>
void Simulation<D>::report_non_finite(std::size_t index) {
  non_finite_index_ = SIZE_MAX;
  const std::int64_t pid = p_.id[index];
  std::string detail;
  // Name the strongest contact on that particle, the usual culprit.
  double strongest = -1;
  for_each_model([&](auto model_index) {
    constexpr int I = decltype(model_index)::value;
    using M = ContactModelAt<I>;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (b.i[k] != index && b.j[k] != index) continue;
      std::uint32_t other = b.i[k] == index ? b.j[k] : b.i[k];
      double overlap = p_.radius[index] + p_.radius[other] -
                       separation(p_.position[index], p_.position[other]).norm();
      if (!(overlap > strongest) && std::isfinite(overlap)) continue;
      strongest = std::isfinite(overlap) ? overlap : 1e300;
      detail = fmt::format("; its contact with particle {} ({} model, overlap {:.4g} m)",
                           p_.id[other], M::name, overlap);
    }
  });
  fail(fmt::format("step {} (t = {:.6g} s): particle {} has a non-finite position, velocity or "
                   "spin (force {} {}){}; time step {:.4g} s",
                   step_, time_, pid, p_.force_torque[index].force[0],
                   p_.force_torque[index].force[1], detail, dt_),
       "its last finite state");
}

template <int D>
void Simulation<D>::sort_particles() {
  if (p_.size() < 2) return;
  // The last step's contact log names storage indices: kept by id first, for a
  // failure this rebuild reports (check_escapes) and the state it keeps.
  keep_contacts_by_id();
  sort_along_curve(p_);
  // Histories are keyed by id: rebuild the lists for the new storage order.
  rebuild_lists();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
