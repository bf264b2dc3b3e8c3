#include "engine/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <type_traits>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/errors.hpp"
#include "kernel/pair_batch.hpp"
#include "core/random.hpp"

namespace granule {

namespace {
using Clock = std::chrono::steady_clock;
// Contacts ahead whose history and velocities the pair loop asks the cache for.
constexpr std::size_t prefetch_distance = 16;
// Pass 1 runs ~3x faster per entry than the force pass: it fetches further ahead.
// Both leads doubled in stop 16 (force and torque now share a line, so fewer
// lines are in flight per contact): 3-4 % off the pair loop in the packing.
constexpr std::int64_t pass1_prefetch_distance = 64;
constexpr std::int64_t prefetch_min_candidates = 1 << 16;
// The wall loop's particles ahead (the candidates name particles in memory
// order, but sparsely: those near a wall).
constexpr std::int64_t wall_prefetch_distance = 8;
constexpr std::int64_t wall_prefetch_min_candidates = 1 << 13;
// Candidates per block of the pair loop: its listing pass, then its force pass
// while the block's data are in the caches (~300 contacts in the dense box).
constexpr std::int64_t pair_block = 2048;
// The pair loop's listing pass: over all candidates, the same noting those
// near enough to keep (pruning), or over the noted ones only.
constexpr int full_pass = 0, note_pass = 1, near_pass = 2;

// Runs a contact kernel's work(t, nt, touching, max_ratio) on a team of
// threads (an OpenMP region) or, for a team of one, directly: summing the
// contact counts and taking the largest overlap ratio.
template <typename Work>
void run_on_team(int team, Work& work, std::int64_t& touching_out, double& max_ratio_out) {
  std::int64_t touching = 0;
  double max_ratio = 0;
  if (team > 1) {
#pragma omp parallel num_threads(team) reduction(+ : touching) reduction(max : max_ratio)
    work(omp_get_thread_num(), omp_get_num_threads(), touching, max_ratio);
  } else {
    work(0, 1, touching, max_ratio);
  }
  touching_out += touching;
  if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
}
// Runs range(lo, hi) over the particles [0, n): split among a team of threads
// (an OpenMP region, each thread a contiguous part) when `parallel`, else once.
template <typename Range>
void over_particles(bool parallel, int threads, std::int64_t n, Range&& range) {
  if (!parallel) return range(std::int64_t{0}, n);
#pragma omp parallel num_threads(threads)
  {
    const std::int64_t t = omp_get_thread_num(), nt = omp_get_num_threads();
    range(n * t / nt, n * (t + 1) / nt);
  }
}
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
  auto t0 = Clock::now();
  // 1. Neighbour lists: rebuilt only when something moved more than half the skin.
  // Large scenes are re-sorted along a space-filling curve every 32nd rebuild.
  if (!lists_valid_ || lists_stale()) {
    if (p_.size() >= sort_min_particles && rebuilds_ % 32 == 0)
      sort_particles();
    else
      rebuild_lists();
  }
  auto t1 = Clock::now();
  stage_times_.neighbor += std::chrono::duration<double>(t1 - t0).count();

  // 2. Contact forces: one inlined kernel per contact model, each contact
  // writing its own slot. The contact log is filled only on steps where the
  // scene records contacts or an attached diagnostic needs them.
  bool observed = record_contacts_ || tracking_;
  for (const auto& d : diagnostics_)
    if (d.needs.contacts && step_ % d.every == 0) observed = true;
  if (observed) log_.resize(slot_count_);
  log_.filled = observed;
  contacts_particle_ = contacts_wall_ = contacts_batched_ = candidates_visited_ = 0;
  max_overlap_ratio_ = 0;
  // Every thread count adds the contacts to each particle in slot order (pairs
  // model by model, then walls), so the result is bit-identical whatever the
  // number of threads. Pair contacts add their forces at once (pair_forces
  // defers those of the particles two threads share); so do wall contacts, each
  // thread owning whole particles (wall_forces). The reactions on the walls
  // are summed at once on one thread ("fused"); on more each contact leaves
  // its part in its list and scatter_forces() sums them in slot order. A scene
  // whose candidates are all below the parallel threshold runs every contact
  // loop on one thread.
  fused_ = thread_count() == 1 || static_cast<std::int64_t>(slot_count_) < parallel_min_candidates_;
  zero_forces();
  for (auto& w : walls_) w.force.setZero(), w.axial_torque = 0;
  // Pruned pair lists are noted afresh once two particles may have closed the
  // prune distance between them, each having moved at most prune_travel_.
  prune_due_ = !(2 * prune_travel_ < prune_distance());
  if (prune_due_) prune_travel_ = 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    auto& pb = std::get<I>(pair_buckets_);
    if (!pb.size()) return;
    if (observed)
      pair_forces<M, true>(pb, pairs_.params<I>());
    else
      pair_forces<M, false>(pb, pairs_.params<I>());
  });
  // The pairs' deepest overlap / smaller radius, before the walls add theirs.
  const double pair_overlap_ratio = max_overlap_ratio_;
  const auto walls_start = Clock::now();
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    auto& wb = std::get<I>(wall_buckets_);
    if (!wb.size()) return;
    if (observed)
      wall_forces<M, true>(wb, pairs_.params<I>());
    else
      wall_forces<M, false>(wb, pairs_.params<I>());
  });
  stage_times_.walls += seconds_since(walls_start);
  // The reactions on the walls (the inner-piece force of 4.4.1), summed in
  // slot order.
  if (!fused_) {
    const auto scatter_start = Clock::now();
    scatter_forces();
    stage_times_.scatter += std::chrono::duration<double>(Clock::now() - scatter_start).count();
  }
  if (observed) list_logged_slots();  // simulation_log.cpp
  // One comparison a step; the contacts are looked at only when it fails.
  if (pair_overlap_ratio > overlap_warning_)
    check_overlaps(pair_overlap_ratio);
  else
    scene_overlaps_ = false;
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
  if (non_finite_index_ != SIZE_MAX) report_non_finite(non_finite_index_);
  time_ += dt_;
  ++step_;
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
  for (std::int64_t s = 0; s < steps; ++s) step();
}

// ----------------------------------------------------------------------------
// Contact kernels. Observed = false is the plain loop; Observed = true also
// writes the contact log. Each contact k writes only its own history, flag and
// log slot (offset + k), so the loop runs in parallel; the sums per particle
// are made in slot order whatever the thread count (see below).
// ----------------------------------------------------------------------------
template <int D>
template <typename M, bool Observed>
void Simulation<D>::pair_forces(PairBucket<D, M>& b,
                                const std::vector<typename M::Params>& params) {
  using History = typename M::template History<D>;
  const std::int64_t count = static_cast<std::int64_t>(b.size());
  std::int64_t touching = 0;
  double max_ratio = 0;
  const int team = count >= parallel_min_candidates_ ? thread_count() : 1;
  b.touched.resize(team);
  // 3D pairs of a model with a batched kernel (contact_batch.hpp) take it.
  constexpr bool batchable = D == 3 && has_force_batch<M>::value;
  if (b.law == -2) {  // once per list: do all candidates share one law (no index to load)?
    b.law = count ? static_cast<std::int64_t>(b.slot[0]) : -1;
    for (const std::uint32_t s : b.slot)
      if (s != b.slot[0]) b.law = -1;
  }
  // Threads take contiguous ranges of candidates (b.split). A particle that
  // only one range reaches gets its forces added by that thread as they come,
  // in slot order; one that several ranges reach (a thin layer where the
  // ranges meet, in space-filling-curve order) gets all of them deferred and
  // added after the others, still in slot order. Either way the sum is the
  // single thread's, bit for bit, wherever the ranges meet: they are moved
  // (rebalance) when the contacts gather in one of them.
  const std::size_t n = p_.size();
  if (team > 1) {
    if (b.split.size() != static_cast<std::size_t>(team) + 1 || b.shared.size() != n) {
      // The ranges carried over from the last lists with their timings
      // (rebuild_lists), else equal ones.
      const bool carried = b.split.size() == static_cast<std::size_t>(team) + 1 &&
                           b.split.front() == 0 && b.split.back() == count &&
                           b.pace.seconds.size() == static_cast<std::size_t>(team);
      if (carried) {
        mark_shared(b);
      } else {
        std::vector<std::int64_t> equal(team + 1);
        for (int t = 0; t <= team; ++t) equal[t] = count * t / team;
        set_split(b, std::move(equal));
        b.pace.moved = false;
      }
    }
    if (deferred_.size() < static_cast<std::size_t>(team)) deferred_.resize(team);
  }
  // Lists of threads that do not run this step (below) must not name old contacts.
  for (auto& list : b.touched) list.count = 0;
  // Pruning (set_pruning). On a step that notes, the listing pass runs over all
  // candidates and also notes, per thread, those in contact or within the prune
  // distance of touching; until the next note it runs over those only. A
  // candidate left out cannot touch: it was not in contact and its particles,
  // each moving at most prune_travel_ since, cannot have closed the distance
  // (a new contact needs overlap > 0, adhesive ones too: a contact that holds
  // on at a gap was in contact when noted). The listing, hence every result,
  // is the same as without pruning. The notes are for this team's ranges.
  const bool pruning = pruning_ && count > 0;
  // Notes not renewed at a global prune (pruning off meanwhile) are stale.
  if (!pruning) b.near_valid = false;
  const bool note_near =
      pruning && (prune_due_ || !b.near_valid || b.near.size() != static_cast<std::size_t>(team) ||
                  b.near_split != b.split);
  const bool use_near = pruning && !note_near && b.near_pays;
  if (note_near) b.near.resize(team);
  const double prune_distance_m = prune_distance();
  if (use_near) {
    for (const auto& near : b.near) candidates_visited_ += static_cast<std::int64_t>(near.size());
  } else {
    candidates_visited_ += count;
  }
  // The work of thread t of nt, called directly on one thread and from an
  // OpenMP region on more. Its arrays are local pointers declared inside:
  // captured by reference, or shared with an OpenMP region, they would be
  // reloaded after every store (Eigen's packet stores may alias anything).
  auto work = [&](std::int64_t t, std::int64_t nt, std::int64_t& touching_out,
                  double& max_ratio_out) {
    // OpenMP may give a region fewer threads than asked for (OMP_DYNAMIC, a
    // thread limit, a region nested in another): the ranges and the shared
    // marks are for `team`, so a smaller team runs the whole bucket on its
    // first thread, as one thread would. The same for every thread of the
    // team, so they all meet the same barriers.
    if (nt != team && t != 0) return;
    const bool sharing = nt == team && nt > 1;
    if (t == 0) b.ran_team = static_cast<int>(nt);
    const double dt = dt_;
    const std::uint32_t* const bi = b.i.data();
    const std::uint32_t* const bj = b.j.data();
    const std::uint32_t* const bslot = b.slot.data();
    History* const hist = b.history.data();
    const typename M::Params* const par_of = params.data();
    const bool one_law = b.law >= 0;
    const V* const x = p_.position.data();
    const V* const v = p_.velocity.data();
    const S* const w = p_.spin.data();
    const double* const radius = p_.radius.data();
    const double* const inv_mass = p_.inv_mass.data();
    std::uint8_t* const in_contact = slot_in_contact_.data() + b.offset;
    ForceTorque<D>* const load = p_.force_torque.data();
    const std::uint8_t* const shared = sharing ? b.shared.data() : nullptr;
    std::vector<Deferred>* const deferred = sharing ? &deferred_[t] : nullptr;
    if (deferred) deferred->clear();
    const Periodicity periodic = periodic_;
    const bool periodic_on = periodic.on();
    const int periodic_axis = periodic_on ? periodic.axis : 0;
    const std::size_t offset = b.offset;
    std::int64_t touching = 0;
    double max_ratio = 0;
    const auto started = sharing ? Clock::now() : Clock::time_point{};  // for rebalance()
    const std::int64_t begin = sharing ? b.split[t] : 0, end = sharing ? b.split[t + 1] : count;
    StepList<D>& list = b.touched[t];
    list.start(static_cast<std::size_t>(end - begin));
    // The list's array and count in registers.
    std::uint32_t* const listing = list.entries.data();
    std::size_t listed = 0;
    // Pruning: this thread's noted candidates, written on a noting step, read
    // on the others (not when OpenMP gave a smaller team: then the ranges differ).
    const bool noting = note_near && nt == team, near_only = use_near && nt == team;
    HotArray<std::uint32_t>* const near = noting || near_only ? &b.near[t] : nullptr;
    if (noting) near->resize(static_cast<std::size_t>(end - begin));
    std::uint32_t* const noted_out = noting ? near->data() : nullptr;
    const std::uint32_t* const near_in = near_only ? near->data() : nullptr;
    const std::int64_t near_count = near_only ? static_cast<std::int64_t>(near->size()) : 0;
    std::size_t noted = 0;
    // Small scenes live in the caches, where prefetching only costs.
    const bool prefetch = count >= prefetch_min_candidates;
    // The batch reads the masses only on a contact's first step (batch_needs_mass).
    const bool fetch_masses = !(batchable && batched_contacts_);
    // Pass 1, a tight loop over a block of candidates, lists those that touch
    // and those that stopped touching and must be cleared; most do neither
    // (the Mechanofusion base case has ~10x more candidates than contacts), and
    // kept apart from the force code this loop holds its few values in
    // registers. No branch: "touches or was in contact" is a bitwise or (a ||
    // would branch, and mispredict).
    // Entries e run over the candidates k themselves, or over the noted ones
    // (pruning: Mode near_pass).
    auto pass1 = [&](auto periodic_c, auto mode_c, std::int64_t from, std::int64_t to) {
      constexpr int Mode = decltype(mode_c)::value;
      for (std::int64_t e = from; e < to; ++e) {
        const std::int64_t k = Mode == near_pass ? near_in[e] : e;
        const std::uint32_t i = bi[k], j = bj[k];
        // The partner's position and radius fetched ahead: neighbours along
        // the space-filling curve can lie far apart in memory.
        if (prefetch && e + pass1_prefetch_distance < to) {
          const std::int64_t ahead = e + pass1_prefetch_distance;
          const std::uint32_t j_ahead = bj[Mode == near_pass ? near_in[ahead] : ahead];
          __builtin_prefetch(&x[j_ahead]);
          __builtin_prefetch(&radius[j_ahead]);
        }
        V d = x[i] - x[j];
        if constexpr (decltype(periodic_c)::value)
          d[periodic_axis] = periodic.wrap(d[periodic_axis]);
        const double dist_sq = d.squaredNorm();
        const double r_sum = radius[i] + radius[j];
        bool touches = M::adhesive || dist_sq < r_sum * r_sum;
        if constexpr (M::adhesive)
          touches = M::touching(par_of[bslot[k]], hist[k], r_sum - std::sqrt(dist_sq));
        const std::uint32_t touch_bit = touches ? 1u : 0u;
        const std::uint32_t was_in_contact = in_contact[k];
        listing[listed] = static_cast<std::uint32_t>(k) << 1 | touch_bit;
        listed += touch_bit | was_in_contact;
        if constexpr (Mode == note_pass) {
          const double reach = r_sum + prune_distance_m;
          noted_out[noted] = static_cast<std::uint32_t>(k);
          noted += (dist_sq < reach * reach ? 1u : 0u) | was_in_contact;
        }
      }
    };
    // A force and torque onto particle p: at once, or deferred when two
    // threads' ranges share p (added after the barrier below). The arrays come
    // as arguments: reached through a closure (the batch's flush is not
    // inlined) they would be reloaded after every store.
    auto add_to = [](ForceTorque<D>* const ft, const std::uint8_t* const shared_mark,
                     std::vector<Deferred>* const later, std::uint32_t p, const V& force,
                     const S& torque) __attribute__((always_inline)) {
      if (!shared_mark || !shared_mark[p]) {
        ft[p].force += force;
        ft[p].torque += torque;
      } else {
        later->push_back({p, force, torque});
      }
    };
    // A contact's force and torques onto i and j (j feels -total; a + (-b) is a - b).
    auto add = [&](std::uint32_t i, std::uint32_t j, const V& total, const S& torque_i,
                   const S& torque_j) __attribute__((always_inline)) {
      add_to(load, shared, deferred, i, total, torque_i);
      add_to(load, shared, deferred, j, V(-total), torque_j);
      ++touching;
    };
    // Fetches ahead the data of the contact `distance` entries on in the list.
    auto prefetch_contact = [&](std::uint32_t ahead) __attribute__((always_inline)) {
      const std::uint32_t i_ahead = bi[ahead], j_ahead = bj[ahead];
      __builtin_prefetch(&hist[ahead]);
      if (!one_law) __builtin_prefetch(&bslot[ahead]);
      __builtin_prefetch(&v[j_ahead]);
      __builtin_prefetch(&w[j_ahead]);
      __builtin_prefetch(&v[i_ahead]);
      __builtin_prefetch(&w[i_ahead]);
      if (fetch_masses) __builtin_prefetch(&inv_mass[j_ahead]);
      __builtin_prefetch(&load[j_ahead], 1);  // force and torque: one line
    };
    // Entry e of a block's list, for both second passes: fetches a few entries
    // ahead (the contacts are sparse in the candidate arrays), clears a
    // history whose contact ended (false), else gives the candidate k and its
    // particles.
    auto open_entry = [&](std::size_t e, std::size_t e_end, std::uint32_t & k, std::uint32_t & i,
                          std::uint32_t & j) __attribute__((always_inline)) {
      if (prefetch && e + prefetch_distance < e_end)
        prefetch_contact(listing[e + prefetch_distance] >> 1);
      const std::uint32_t entry = listing[e];
      k = entry >> 1;
      if (!(entry & 1)) {  // the history was in use: clear it once
        hist[k] = History{};
        in_contact[k] = 0;
        return false;
      }
      i = bi[k], j = bj[k];
      return true;
    };
    // Pass 2 works through the block's list while its candidates' and
    // particles' data are still in the caches.
    // Inlined: called through its closure it would reach every array through
    // a pointer and reload them after each store (as captured ones, above).
    auto pass2 = [&](std::size_t e_begin, std::size_t e_end) __attribute__((always_inline)) {
      for (std::size_t e = e_begin; e < e_end; ++e) {
        std::uint32_t k, i, j;
        if (!open_entry(e, e_end, k, i, j)) continue;
        V d = x[i] - x[j];
        if (periodic_on) d[periodic_axis] = periodic.wrap(d[periodic_axis]);
        History& h = hist[k];
        const double r_sum = radius[i] + radius[j];
        // |d| and 1/|d| from a square root and a division that run side by
        // side, rather than one after the other on the contact's critical path.
        const double dist_sq = d.squaredNorm();
        const double dist = std::sqrt(dist_sq);
        const double inv_dist = dist * (1.0 / dist_sq);
        const double overlap = r_sum - dist;
        const typename M::Params& par = par_of[one_law ? b.law : bslot[k]];
        in_contact[k] = 1;
        ContactState<D> c;
        c.dt = dt;
        // Coincident centres: any direction is as good as another, but it must be finite.
        c.normal = dist > 0 ? V(d * inv_dist) : V(V::UnitX());
        c.overlap = overlap;
        const V v_rel = v[j] - v[i];
        c.normal_velocity = v_rel.dot(c.normal);
        // Eq. 3.10: tangential slip of j's surface relative to i's.
        c.tangential_velocity = v_rel - c.normal * c.normal_velocity +
                                Dim<D>::spin_cross(radius[i] * w[i] + radius[j] * w[j], c.normal);
        // Divisions only for the models that read them (see contact_state.hpp).
        c.inv_mass_sum = inv_mass[i] + inv_mass[j];
        if constexpr (uses_effective_mass<M>::value)
          c.effective_mass = 1.0 / (inv_mass[i] + inv_mass[j]);
        else
          c.effective_mass = std::numeric_limits<double>::quiet_NaN();
        if constexpr (uses_effective_radius<M>::value)
          c.effective_radius = radius[i] * radius[j] / r_sum;
        else
          c.effective_radius = std::numeric_limits<double>::quiet_NaN();
        const ContactForce<D> f = M::force(par, h, c);
        const V total = f.normal * c.normal + f.tangential;
        // Torques about each centre, applied at the contact point: lever -(r_i - a/2) n
        // on i and +(r_j - a/2) n on j (which feels -T). With these levers the pair
        // exerts no net torque, so angular momentum is conserved to round-off.
        const S n_cross_t = Dim<D>::torque(c.normal, f.tangential);
        const S torque_i = -(radius[i] - 0.5 * overlap) * n_cross_t;
        const S torque_j = -(radius[j] - 0.5 * overlap) * n_cross_t;
        add(i, j, total, torque_i, torque_j);
        // The largest overlap / smaller radius, without a division per contact.
        const double r_min = std::min(radius[i], radius[j]);
        if (overlap > max_ratio * r_min) max_ratio = overlap / r_min;
        if constexpr (Observed) {
          const std::size_t s = offset + k;
          log_.record(s, static_cast<std::int32_t>(i), static_cast<std::int32_t>(j), overlap,
                      f.normal, c.normal_velocity, c.normal, f.tangential,
                      x[i] - (radius[i] - 0.5 * overlap) * c.normal);
        }
      }
    };
    auto blocks = [&](auto&& second_pass) __attribute__((always_inline)) {
      const std::int64_t first_e = near_only ? 0 : begin, last_e = near_only ? near_count : end;
      auto listing_pass = [&](auto periodic_c, std::int64_t from, std::int64_t to) {
        if (near_only)
          pass1(periodic_c, std::integral_constant<int, near_pass>{}, from, to);
        else if (noting)
          pass1(periodic_c, std::integral_constant<int, note_pass>{}, from, to);
        else
          pass1(periodic_c, std::integral_constant<int, full_pass>{}, from, to);
      };
      for (std::int64_t from = first_e; from < last_e; from += pair_block) {
        const std::int64_t to = std::min(last_e, from + pair_block);
        const std::size_t first = listed;
        if (periodic_on)
          listing_pass(std::true_type{}, from, to);
        else
          listing_pass(std::false_type{}, from, to);
        second_pass(first, listed);
      }
    };
    bool by_batch = false;
    if constexpr (batchable) {
      // Pass 2 by batches (pair_batch.hpp) when the model offers force_batch:
      // the contacts' data gathered in slot order, geometry and law computed
      // lane by lane, the results added in slot order.
      if (batched_contacts_) {
        by_batch = true;
        PairBatch<M> batch;
        batch.c.dt = dt;
        auto flush = [&]() {
          batch.lanes_in();
          batch.pad();
          batch.geometry();
          M::force_batch(batch.params, batch.history, batch.c);
          batch.totals();
          batch.lanes_out();
          // The arrays as locals (this closure is not inlined: see add_to).
          ForceTorque<D>* const ft = load;
          const std::uint8_t* const shared_mark = shared;
          std::uint8_t* const flags = in_contact;
          History* const histories = hist;
          std::vector<Deferred>* const later = deferred;
          const int lanes_used = batch.count;
          double worst = max_ratio;
          // Each lane's results onto its particles at once, in slot order.
          for (int l = 0; l < lanes_used; ++l) {
            const std::uint32_t k = batch.k[l], i = batch.i[l], j = batch.j[l];
            flags[k] = 1;
            batch.store_history(l, histories[k]);
            if (!shared_mark || !shared_mark[i])
              batch.add_i(ft[i], l);
            else
              later->push_back({i, batch.force_on_i(l), batch.torque_on_i(l)});
            if (!shared_mark || !shared_mark[j])
              batch.add_j(ft[j], l);
            else
              later->push_back({j, V(-batch.force_on_i(l)), batch.torque_on_j(l)});
            const double overlap = batch.c.overlap[l];
            const double r_min = std::min(batch.r_i[l], batch.r_j[l]);
            if (overlap > worst * r_min) worst = overlap / r_min;
            if constexpr (Observed) {
              const V normal(batch.c.nx[l], batch.c.ny[l], batch.c.nz[l]);
              log_.record(offset + k, static_cast<std::int32_t>(i), static_cast<std::int32_t>(j),
                          overlap, batch.c.normal_force[l], batch.c.normal_velocity[l], normal,
                          V(batch.c.ftx[l], batch.c.fty[l], batch.c.ftz[l]),
                          x[i] - (batch.r_i[l] - 0.5 * overlap) * normal);
            }
          }
          touching += lanes_used;
          max_ratio = worst;
          batch.count = 0;
        };
        // Each lane read from its contact's particles (gather_lane).
        auto gather = [&](std::size_t e_begin, std::size_t e_end) __attribute__((always_inline)) {
          for (std::size_t e = e_begin; e < e_end; ++e) {
            std::uint32_t k, i, j;
            if (!open_entry(e, e_end, k, i, j)) continue;
            const int l = batch.count++;
            batch.k[l] = k, batch.i[l] = i, batch.j[l] = j;
            batch.params[l] = &par_of[one_law ? b.law : bslot[k]];
            const History& h = hist[k];
            batch.gather_lane(l, x[i], x[j], v[i], v[j], w[i], w[j], radius[i], radius[j],
                              batch_needs_mass<M>(h) ? inv_mass[i] + inv_mass[j] : 1.0, h);
            if (periodic_on) {
              double& along = batch.separation(l, periodic_axis);
              along = periodic.wrap(along);
            }
            if (batch.count == batch.lanes) flush();
          }
        };
        blocks(gather);
        if (batch.count) flush();
      }
    }
    if (!by_batch) blocks(pass2);
    list.count = listed;
    if (noting) near->resize(noted);
    if (sharing) {
      // What this thread did, for rebalance(): each thread writes only its own entries.
      const auto arrived = Clock::now();
      b.pace.seconds[t] += std::chrono::duration<double>(arrived - started).count();
      b.pace.candidates[t] += static_cast<double>(end - begin);
      b.pace.listed[t] += static_cast<double>(listed);
      // The deferred contributions, thread by thread (each in its range's
      // order): slot order. Each thread adds those to its own particles (shared_split).
#pragma omp barrier
      const auto deferred_start = Clock::now();
      const double waited = std::chrono::duration<double>(deferred_start - arrived).count();
#pragma omp atomic
      stage_times_.pair_wait += waited;
      const std::uint32_t lo = b.shared_split[t], width = b.shared_split[t + 1] - lo;
      for (std::int64_t u = 0; u < nt; ++u)
        for (const Deferred& d : deferred_[u])
          if (d.particle - lo < width) {
            load[d.particle].force += d.force;
            load[d.particle].torque += d.torque;
          }
      if (t == 0) stage_times_.scatter += seconds_since(deferred_start);  // only thread 0 writes
    }
    touching_out += touching;
    if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
  };
  run_on_team(team, work, touching, max_ratio);
  if (note_near) {
    // Notes taken by a smaller team than asked for are not per range: unused.
    b.near_valid = b.ran_team == team;
    b.near_split = b.split;
    std::size_t noted = 0;
    for (const auto& near : b.near) noted += near.size();
    // The noted pass reads one index more per candidate: worth it below ~80 %.
    b.near_pays = 5 * noted <= 4 * static_cast<std::size_t>(count);
    ++prunes_;
  }
  if (team > 1 && b.ran_team == team) rebalance(b, team);
  contacts_particle_ += touching;
  if (batchable && batched_contacts_) contacts_batched_ += touching;
  if (max_ratio > max_overlap_ratio_) max_overlap_ratio_ = max_ratio;
}

// Which particles the threads' candidate ranges (b.split) share
// (pair_forces): those some candidate of two ranges names, that is, whose
// first and last naming candidates lie in two ranges (they are contiguous).
// Timed as part of the fixed-order sums (sim:timings().scatter).
template <int D>
template <typename M>
void Simulation<D>::mark_shared(PairBucket<D, M>& b) {
  const auto start = Clock::now();
  const std::size_t n = p_.size();
  constexpr std::uint32_t none = ~0u;
  if (b.first_named.size() != n) {  // once per list
    b.first_named.assign(n, none);
    b.last_named.assign(n, 0);
    const std::size_t count = b.size();
    for (std::size_t k = 0; k < count; ++k)
      for (const std::uint32_t p : {b.i[k], b.j[k]}) {
        if (b.first_named[p] == none) b.first_named[p] = static_cast<std::uint32_t>(k);
        b.last_named[p] = static_cast<std::uint32_t>(k);
      }
  }
  const int team = static_cast<int>(b.split.size()) - 1;
  b.shared.assign(n, 0);
  std::size_t shared = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const std::uint32_t first = b.first_named[p], last = b.last_named[p];
    if (first == none) continue;
    // A cut between them (split[r] is where range r starts).
    for (int r = 1; r < team; ++r)
      if (static_cast<std::int64_t>(first) < b.split[r] &&
          b.split[r] <= static_cast<std::int64_t>(last)) {
        b.shared[p] = 1;
        ++shared;
        break;
      }
  }
  // The deferred forces are added thread by thread, each to its own
  // particles: cut those so that each thread gets its share of the shared
  // ones (they lie around where the ranges meet, not where the particles'
  // halves do).
  b.shared_split.assign(team + 1, static_cast<std::uint32_t>(n));
  b.shared_split[0] = 0;
  std::size_t seen = 0;
  int next = 1;
  for (std::size_t p = 0; p < n && next < team; ++p) {
    while (next < team && seen >= shared * next / team)
      b.shared_split[next++] = static_cast<std::uint32_t>(p);
    seen += b.shared[p];
  }
  stage_times_.scatter += seconds_since(start);
}

// Moves the threads' candidate ranges when one thread is busier than the
// others: a pile in one part of the candidates, or a thread the host slows
// down (the cores are shared). The work is modelled as one unit per candidate
// (the listing pass) and `contact_weight` units per listed contact, the weight
// fitted to the threads' measured times (it depends on the model and the
// machine: ~11 for the linear law on this project's machine). Each thread's
// pace, units per second over the steps judged, sets its share: the new cut
// points share this step's candidates and listed contacts out in proportion
// (so a range whose units cost more, or a slower thread, gets fewer). Judged
// every 16 steps, acting on a spread of more than 3 % between the busiest
// thread and the mean: moving the ranges costs a pass over the particles
// (mark_shared). The forces do not depend on where the ranges meet, so
// neither do the results.
template <int D>
template <typename M>
void Simulation<D>::rebalance(PairBucket<D, M>& b, int team) {
  constexpr std::int64_t min_interval = 16;
  ++b.pace.steps;
  if (b.pace.moved && b.pace.steps < min_interval) return;
  double most = 0, sum = 0;
  for (int t = 0; t < team; ++t) {
    most = std::max(most, b.pace.seconds[t]);
    sum += b.pace.seconds[t];
  }
  if (!(most * team > 1.03 * sum)) {
    if (b.pace.steps >= 4 * min_interval) b.pace.reset(team);  // judge recent steps
    return;
  }
  // Least squares for time = a candidates + c listed over the threads; the
  // weight c / a, blended with the last one, when the threads' mixes differ.
  double cc = 0, cl = 0, ll = 0, ct = 0, lt = 0;
  for (int t = 0; t < team; ++t) {
    const double c = b.pace.candidates[t], l = b.pace.listed[t], time = b.pace.seconds[t];
    cc += c * c, cl += c * l, ll += l * l, ct += c * time, lt += l * time;
  }
  const double det = cc * ll - cl * cl;
  if (det > 1e-3 * cc * ll) {
    const double a = (ct * ll - lt * cl) / det, c = (lt * cc - ct * cl) / det;
    if (a > 0 && c > 0)
      b.pace.contact_weight = std::clamp(0.5 * (b.pace.contact_weight + c / a), 1.0, 200.0);
  }
  ++rebalances_;
  // Walk the candidates with the listed ones (in increasing k across the
  // lists) and cut where the cumulative cost reaches each thread's share.
  const std::int64_t count = static_cast<std::int64_t>(b.size());
  std::int64_t listed = 0;
  for (const auto& list : b.touched) listed += static_cast<std::int64_t>(list.count);
  const double weight = b.pace.contact_weight;
  const double total = static_cast<double>(count) + weight * static_cast<double>(listed);
  // The threads' paces, and where each cut falls as a fraction of the total.
  std::vector<double> share(team + 1, 0.0);
  bool paced = true;
  for (int t = 0; t < team; ++t) {
    const double units = b.pace.candidates[t] + weight * b.pace.listed[t];
    share[t + 1] = b.pace.seconds[t] > 0 ? units / b.pace.seconds[t] : 0;
    paced = paced && share[t + 1] > 0 && std::isfinite(share[t + 1]);
  }
  for (int t = 1; t <= team; ++t) share[t] = paced ? share[t - 1] + share[t] : t;
  std::vector<std::int64_t> split(team + 1, count);
  split[0] = 0;
  int next = 1;
  std::int64_t listed_before = 0;
  auto cut_until = [&](std::int64_t k) {  // cuts that fall at or before candidate k
    while (next < team && static_cast<double>(k) + weight * static_cast<double>(listed_before) >=
                              total * share[next] / share[team])
      split[next++] = k;
  };
  for (const auto& list : b.touched)
    for (const std::uint32_t entry : list) {
      cut_until(entry >> 1);
      ++listed_before;
    }
  cut_until(count);
  set_split(b, std::move(split));
  b.pace.moved = true;
}

// New ranges for the threads: which particles they share, and fresh timings.
template <int D>
template <typename M>
void Simulation<D>::set_split(PairBucket<D, M>& b, std::vector<std::int64_t> split) {
  b.split = std::move(split);
  mark_shared(b);
  b.pace.reset(static_cast<int>(b.split.size()) - 1);
}

template <int D>
template <typename M, bool Observed>
void Simulation<D>::wall_forces(WallBucket<D, M>& b,
                                const std::vector<typename M::Params>& params) {
  using History = typename M::template History<D>;
  const std::int64_t count = static_cast<std::int64_t>(b.size());
  const std::size_t offset = b.offset;
  std::int64_t touching = 0;
  double max_ratio = 0;
  const int threads = thread_count();
  // Wall contacts cost more per candidate than pairs (each one reaches a
  // particle's data on its own), so they go parallel from a smaller list.
  const int team = !fused_ && count >= parallel_min_candidates_ / 8 ? threads : 1;
  b.touched.resize(team);
  // OpenMP may run fewer threads than asked for (see pair_forces): the ranges
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
    const typename M::Params* const par_of = params.data();
    const Wall<D>* const walls = walls_.data();
    const V* const x = p_.position.data();
    const V* const v = p_.velocity.data();
    const S* const w_spin = p_.spin.data();
    const double* const radius = p_.radius.data();
    const double* const mass = p_.mass.data();
    const double* const inv_mass = p_.inv_mass.data();
    std::uint8_t* const in_contact = slot_in_contact_.data() + offset;
    const bool fused = fused_;
    ForceTorque<D>* const load = p_.force_torque.data();
    const double dt = dt_;
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
    for (std::int64_t k = begin; k < end; ++k) {
      if (prefetch && k + wall_prefetch_distance < end) {
        const std::uint32_t ahead = bp[k + wall_prefetch_distance];
        __builtin_prefetch(&x[ahead]);
        __builtin_prefetch(&radius[ahead]);
        __builtin_prefetch(&v[ahead]);
        __builtin_prefetch(&w_spin[ahead]);
        __builtin_prefetch(&load[ahead], 1);
      }
      const std::uint32_t i = bp[k];
      const Wall<D>& w = walls[bw[k]];
      const typename M::Params& par = par_of[bslot[k]];
      History& h = hist[k];
      V n, surface_velocity, lever;
      const double overlap = w.contact(x[i], radius[i], n, surface_velocity, lever);
      if (!M::touching(par, h, overlap)) {
        if (in_contact[k]) {
          h = History{};
          in_contact[k] = 0;
        }
        continue;
      }
      in_contact[k] = 1;
      const std::size_t e = list.count;  // this contact's place in the list
      list.push(static_cast<std::uint32_t>(k) << 1 | 1u);
      ContactState<D> c;
      c.dt = dt;
      c.normal = n;
      c.overlap = overlap;
      const V v_rel = surface_velocity - v[i];
      c.normal_velocity = v_rel.dot(n);
      c.tangential_velocity =
          v_rel - n * c.normal_velocity + radius[i] * Dim<D>::spin_cross(w_spin[i], n);
      c.effective_mass = mass[i];
      c.inv_mass_sum = inv_mass[i];
      const double r = radius[i];
      c.effective_radius = w.effective_radius(r);
      const ContactForce<D> f = M::force(par, h, c);
      const V total = f.normal * n + f.tangential;
      const S torque_i = Dim<D>::torque(-(r - overlap) * n, f.tangential);  // at the wall surface
      const double axial = w.axial_moment(lever, total);
      load[i].force += total;
      load[i].torque += torque_i;
      if (fused) {
        Wall<D>& reacting = walls_[bw[k]];
        reacting.force -= total;
        reacting.axial_torque -= axial;
      } else {
        out_b[e] = bw[k];
        out_force[e] = total;
        out_axial[e] = axial;
      }
      ++touching;
      if (overlap > max_ratio * r) max_ratio = overlap / r;
      if constexpr (Observed) {
        const std::size_t s = offset + k;
        log_.record(s, static_cast<std::int32_t>(i), -1 - static_cast<std::int32_t>(b.wall[k]),
                    overlap, f.normal, c.normal_velocity, n, f.tangential,
                    x[i] - (r - overlap) * n);
      }
    }
    touching_out += touching;
    if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
  };
  run_on_team(team, work, touching, max_ratio);
  contacts_wall_ += touching;
  if (max_ratio > max_overlap_ratio_) max_overlap_ratio_ = max_ratio;
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
      e.effective_radius = walls_[b.wall[k]].effective_radius(p_.radius[b.particle[k]]);
    }
  };
  auto visit = [&](std::size_t k) {
    const std::size_t s = b.offset + k;
    ContactTrack<D>& t = b.track[k];
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
  StepView<D> view{p_, walls_, log_, time_, dt_, step_};
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
  const int threads = thread_count();
  over_particles(
      !fused_ && threads > 1 && n >= parallel_min_particles_, threads, n,
      [&](std::int64_t lo, std::int64_t hi) { std::fill(load + lo, load + hi, ForceTorque<D>{}); });
}

template <int D>
void Simulation<D>::scatter_forces() {
  // The reactions on the walls (the inner-piece force of 4.4.1), in slot
  // order (model by model; within a bucket the threads' lists follow one
  // another in increasing k): the order one thread adds them in, so the sums
  // are bit-identical whatever the threads. The particles' sides were added
  // by wall_forces.
  for_each_model([&](auto index) {
    const auto& b = std::get<decltype(index)::value>(wall_buckets_);
    if (!b.size()) return;
    for (const auto& list : b.touched)
      for (std::size_t e = 0; e < list.count; ++e) {
        Wall<D>& w = walls_[list.b[e]];
        w.force -= list.force[e];
        w.axial_torque -= list.axial[e];
      }
  });
}

// ----------------------------------------------------------------------------
// Integration, in parallel over particles. Leap-frog: a = F/m and dw/dt = M/I
// (SPEC 2: Eq. 4.7's minus sign belongs to its force convention).
// ----------------------------------------------------------------------------
template <int D>
void Simulation<D>::integrate() {
  const std::int64_t n = static_cast<std::int64_t>(p_.size());
  const double dt = dt_;
  const bool body = body_.active();
  const bool periodic = periodic_.on();
  // Spins only when a pair in use has friction; a law changed since prepare()
  // (a friction ramp in a hook) counts as frictional until the next prepare().
  const bool spins = rotation_ || !prepared_;
  double max_sq = max_displacement_sq_;
  double speed_sq = 0;  // the fastest particle's, for pruning (pair_forces)
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();
  const int threads = thread_count();
  const Periodicity pbc = periodic_;
  // One loop per combination of the effects in use (body force, periodic axis,
  // spins, fixed particles), so a scene pays in the particle loop only for
  // what it has: the branches are resolved when the loop is compiled.
  const bool any_fixed = any_fixed_;
  auto range = [&](auto body_c, auto periodic_c, auto spins_c, auto fixed_c, std::int64_t begin,
                   std::int64_t end, double& max_sq_out, double& speed_sq_out,
                   std::int64_t& bad_out) {
    constexpr bool Body = decltype(body_c)::value, Periodic = decltype(periodic_c)::value;
    constexpr bool Spins = decltype(spins_c)::value, Fixed = decltype(fixed_c)::value;
    // The arrays as local pointers: captured by reference they would be
    // reloaded after every store (Eigen's packet stores may alias anything).
    V* const x = p_.position.data();
    V* const v = p_.velocity.data();
    S* const w = p_.spin.data();
    ForceTorque<D>* const load = p_.force_torque.data();
    const V* const x_rebuild = position_at_rebuild_.data();
    const double* const mass = p_.mass.data();
    const double* const inv_mass = p_.inv_mass.data();
    const double* const inv_inertia = p_.inv_inertia.data();
    const std::uint8_t* const fixed = p_.fixed.data();
    const double h = dt;
    const Periodicity periodicity = pbc;
    double max_moved = max_sq_out, fastest = speed_sq_out;
    std::int64_t first_bad = bad_out;
    for (std::int64_t i = begin; i < end; ++i) {
      if constexpr (Fixed)
        if (fixed[i]) continue;  // immobile: its contact force stays for reports
      if constexpr (Body) load[i].force += body_.force(mass[i], x[i]);
      // The new state in registers first: a step that makes it non-finite is
      // not stored, so the failure report writes the last finite state.
      const V v_new = v[i] + load[i].force * (inv_mass[i] * h);  // Eq. 4.8
      V x_new = v_new * h + x[i];                                // Eq. 4.9
      V moved_by = x_new - x_rebuild[i];
      if constexpr (Periodic) {
        double& coordinate = x_new[periodicity.axis];
        coordinate -=
            periodicity.length * std::floor((coordinate - periodicity.origin) / periodicity.length);
        moved_by[periodicity.axis] = periodicity.wrap(moved_by[periodicity.axis]);
      }
      const double moved = moved_by.squaredNorm();
      if (!(moved <= max_moved)) {  // also true for NaN
        if (!std::isfinite(moved) ||
            (Spins &&
             !std::isfinite(Dim<D>::spin_sq(w[i] + load[i].torque * (inv_inertia[i] * h))))) {
          if (i < first_bad) first_bad = i;
          continue;
        }
        max_moved = moved;
      }
      fastest = std::max(fastest, v_new.squaredNorm());  // this step moves i by |v_new| dt
      v[i] = v_new;
      x[i] = x_new;
      if constexpr (Spins) w[i] += load[i].torque * (inv_inertia[i] * h);  // no friction: no torque
    }
    max_sq_out = max_moved;
    speed_sq_out = fastest;
    bad_out = first_bad;
  };
  auto run = [&](auto body_c, auto periodic_c, auto spins_c, auto fixed_c) {
    if (threads > 1 && n >= parallel_min_particles_) {
#pragma omp parallel num_threads(threads) reduction(max : max_sq, speed_sq) reduction(min : bad)
      {
        const std::int64_t t = omp_get_thread_num(), nt = omp_get_num_threads();
        range(body_c, periodic_c, spins_c, fixed_c, n * t / nt, n * (t + 1) / nt, max_sq, speed_sq,
              bad);
      }
    } else {
      range(body_c, periodic_c, spins_c, fixed_c, 0, n, max_sq, speed_sq, bad);
    }
  };
  using yes = std::true_type;
  using no = std::false_type;
  auto with_fixed = [&](auto b, auto p, auto s) {
    any_fixed ? run(b, p, s, yes{}) : run(b, p, s, no{});
  };
  auto with_spins = [&](auto b, auto p) {
    spins ? with_fixed(b, p, yes{}) : with_fixed(b, p, no{});
  };
  auto with_periodic = [&](auto b) { periodic ? with_spins(b, yes{}) : with_spins(b, no{}); };
  body ? with_periodic(yes{}) : with_periodic(no{});
  max_displacement_sq_ = max_sq;
  prune_travel_ += std::sqrt(speed_sq) * dt;
  if (bad != std::numeric_limits<std::int64_t>::max() && non_finite_index_ == SIZE_MAX)
    non_finite_index_ = static_cast<std::size_t>(bad);
  for (auto& wall : walls_) {
    if (wall.type == WallType::plane && !wall.velocity.isZero()) {
      wall.point += wall.velocity * dt;
      wall.moved_since_rebuild += wall.velocity * dt;
    }
  }
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
// Neighbour lists and history transfer
// ----------------------------------------------------------------------------
namespace {
// Compressed rows of old entries by owner id, so each new contact finds its
// old history by scanning only its owner's few old contacts.
struct OwnerIndex {
  std::vector<std::uint32_t> start, order;
  void build(const std::vector<std::int64_t>& owner, std::int64_t max_id) {
    start.assign(static_cast<std::size_t>(max_id) + 2, 0);
    for (auto o : owner) ++start[o + 1];
    for (std::size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
    order.resize(owner.size());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < owner.size(); ++k)
      order[fill[owner[k]]++] = static_cast<std::uint32_t>(k);
  }
};

// Carries history (and tracking state) from `old` to `fresh` for every entry
// whose owner id and partner match; `partner_old(o)` / `partner_new(k)` give
// the second key (the other particle's id, or the wall index).
template <typename Bucket, typename OwnerOf, typename PartnerOld, typename PartnerNew>
void carry_history(const Bucket& old, Bucket& fresh, std::int64_t max_id, bool tracking,
                   const OwnerOf& owner_ids, PartnerOld partner_old, PartnerNew partner_new) {
  fresh.history.assign(fresh.size(), typename Bucket::History{});
  if (tracking) fresh.track.assign(fresh.size(), {});
  if (!old.size()) return;
  OwnerIndex idx;
  idx.build(owner_ids(old), max_id);
  const auto& fresh_owner = owner_ids(fresh);
  const bool carry_track = tracking && old.track.size() == old.size();
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    const std::int64_t owner = fresh_owner[k];
    for (std::uint32_t s = idx.start[owner]; s < idx.start[owner + 1]; ++s) {
      const std::uint32_t o = idx.order[s];
      if (partner_old(o) == partner_new(k)) {
        fresh.history[k] = old.history[o];
        if (carry_track) fresh.track[k] = old.track[o];
        break;
      }
    }
  }
}
}  // namespace

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

template <int D>
void Simulation<D>::rebuild_lists() {
  const std::size_t n = p_.size();
  prune_travel_ = std::numeric_limits<double>::infinity();  // new candidates: prune them all
  any_fixed_ = std::any_of(p_.fixed.begin(), p_.fixed.end(), [](std::uint8_t f) { return f != 0; });
  candidates_.clear();
  grid_.build(p_, skin_, periodic_, candidates_);
  const std::int64_t max_id = p_.next_id;

  std::size_t slots = 0;
  // Pair slots first (all models), then wall slots.
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using B = PairBucket<D, ContactModelAt<I>>;
    B old = std::move(std::get<I>(pair_buckets_));
    B& fresh = std::get<I>(pair_buckets_);
    fresh = B{};
    // The step lists' storage only grows; the arrays start at about the old size.
    fresh.touched = std::move(old.touched);
    fresh.pace = old.pace;  // the machine and model stay (used with a carried split, below)
    for (auto& list : fresh.touched) list.count = 0;  // they named the old candidates
    const std::size_t expect = old.size() + old.size() / 8;
    fresh.i.reserve(expect), fresh.j.reserve(expect), fresh.slot.reserve(expect);
    fresh.id_i.reserve(expect), fresh.id_j.reserve(expect);
    for (auto [a, b] : candidates_) {
      if (p_.id[a] > p_.id[b]) std::swap(a, b);
      const PairTable::Entry& e = pairs_.at(p_.material[a], p_.material[b]);
      if (e.model != I) continue;
      fresh.i.push_back(a);
      fresh.j.push_back(b);
      fresh.slot.push_back(static_cast<std::uint32_t>(e.slot));
      fresh.id_i.push_back(p_.id[a]);
      fresh.id_j.push_back(p_.id[b]);
    }
    carry_history(
        old, fresh, max_id, tracking_, [](const B& x) -> const auto& { return x.id_i; },
        [&](std::uint32_t o) { return old.id_j[o]; }, [&](std::size_t k) { return fresh.id_j[k]; });
    // The threads' ranges keep their shares of the candidates, and what
    // rebalance() has measured of them so far (in a flow the lists are
    // rebuilt every few steps); pair_forces marks the shared particles afresh.
    if (old.split.size() > 1 && old.size() > 0) {
      fresh.split = old.split;
      for (auto& cut : fresh.split)
        cut = static_cast<std::int64_t>(static_cast<double>(cut) / static_cast<double>(old.size()) *
                                        static_cast<double>(fresh.size()));
      fresh.split.front() = 0, fresh.split.back() = static_cast<std::int64_t>(fresh.size());
    }
    fresh.offset = slots;
    slots += fresh.size();
  });
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using WB = WallBucket<D, ContactModelAt<I>>;
    WB old = std::move(std::get<I>(wall_buckets_));
    WB& fresh = std::get<I>(wall_buckets_);
    fresh = WB{};
    fresh.touched = std::move(old.touched);
    for (auto& list : fresh.touched) list.count = 0;
    const std::size_t expect = old.size() + old.size() / 8;
    fresh.particle.reserve(expect), fresh.wall.reserve(expect), fresh.slot.reserve(expect);
    fresh.id.reserve(expect);
    // Particle by particle (then wall by wall): the wall loop then walks the
    // particles' data in memory order, and a particle's wall contacts lie
    // together, so threads can own whole particles (wall_forces).
    for (std::size_t i = 0; i < n; ++i) {
      if (p_.fixed[i]) continue;
      for (std::size_t w = 0; w < walls_.size(); ++w) {
        const PairTable::Entry& e = pairs_.at(p_.material[i], walls_[w].material);
        if (e.model != I) continue;
        if (walls_[w].clearance(p_.position[i], p_.radius[i]) >= skin_) continue;
        fresh.particle.push_back(static_cast<std::uint32_t>(i));
        fresh.wall.push_back(static_cast<std::uint32_t>(w));
        fresh.slot.push_back(static_cast<std::uint32_t>(e.slot));
        fresh.id.push_back(p_.id[i]);
      }
    }
    carry_history(
        old, fresh, max_id, tracking_, [](const WB& x) -> const auto& { return x.id; },
        [&](std::uint32_t o) { return static_cast<std::int64_t>(old.wall[o]); },
        [&](std::size_t k) { return static_cast<std::int64_t>(fresh.wall[k]); });
    fresh.offset = slots;
    slots += fresh.size();
  });
  build_slots();
  check_escapes();  // a particle whose centre passed a wall (simulation_checks.cpp)

  position_at_rebuild_.assign(p_.position.begin(), p_.position.end());
  max_displacement_sq_ = 0;
  for (auto& w : walls_) w.moved_since_rebuild.setZero();
  lists_valid_ = true;
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
  fail(fmt::format(
      "step {} (t = {:.6g} s): particle {} has a non-finite position, velocity or "
      "spin (force {} {}){}; time step {:.4g} s; the output keeps its last finite state",
      step_, time_, pid, p_.force_torque[index].force[0], p_.force_torque[index].force[1], detail,
      dt_));
}

template <int D>
void Simulation<D>::sort_particles() {
  const std::size_t n = p_.size();
  if (n < 2) return;
  // Order along a Morton (Z-order) curve of cells one median diameter wide:
  // particles close in space end up close in memory, so the contact loop reads
  // neighbours from cache. Contact histories follow by persistent id.
  std::vector<double> radii(p_.radius.begin(), p_.radius.end());
  std::nth_element(radii.begin(), radii.begin() + n / 2, radii.end());
  const double cell = 2 * radii[n / 2];
  V lo = p_.position[0];
  for (const auto& x : p_.position) lo = lo.cwiseMin(x);
  constexpr int bits = D == 2 ? 31 : 21;
  const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t k = 0;
    std::uint64_t c[D];
    for (int d = 0; d < D; ++d)
      c[d] = static_cast<std::uint64_t>(
          std::min(top, std::max(0.0, (p_.position[i][d] - lo[d]) / cell)));
    for (int b = bits - 1; b >= 0; --b)
      for (int d = 0; d < D; ++d) k = k << 1 | ((c[d] >> b) & 1u);
    key[i] = k;
  }
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::stable_sort(perm.begin(), perm.end(), [&](auto a, auto b) { return key[a] < key[b]; });
  auto apply = [&](auto& v) {
    auto copy = v;
    for (std::size_t k = 0; k < n; ++k) v[k] = copy[perm[k]];
  };
  apply(p_.position), apply(p_.velocity), apply(p_.force_torque), apply(p_.spin);
  apply(p_.radius), apply(p_.inv_mass), apply(p_.inv_inertia), apply(p_.mass), apply(p_.id);
  apply(p_.material), apply(p_.fixed);
  for (std::size_t k = 0; k < n; ++k) p_.index_of_id[p_.id[k]] = static_cast<std::int32_t>(k);
  // Histories are keyed by id: rebuild the lists for the new storage order.
  rebuild_lists();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
