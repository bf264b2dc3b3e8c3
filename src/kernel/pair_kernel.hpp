// The pair kernel: one step of the contact forces between particles of one
// contact model, over the model's bucket of candidates (buckets.hpp). It owns
// the machinery that makes the loop fast, so the engine sees one call:
//  - blocks of candidates, each a branch-free listing pass (which touch, which
//    just stopped) and then a force pass while the block's data are in the
//    caches, with the partners' data fetched ahead;
//  - pruned lists (pruned_lists.hpp): between notes the listing pass visits
//    only the candidates that can touch;
//  - thread ranges (thread_ranges.hpp): contiguous ranges of candidates per
//    thread, the particles two ranges share deferred and summed after a
//    barrier in slot order, the ranges moved when one thread is busier;
//  - for a model with force_batch in this dimension (contact_batch.hpp), the
//    force pass in batches of lanes (kernel/pair_batch.hpp, pair_batch_2d.hpp).
// Observed = true also writes the contact log (step.log, null otherwise): the
// batched pass by its template argument, the per-contact pass by the pointer at
// run time, so that its arithmetic is the same code whether a step records or
// not (a compiled-in record would give the values it reads other uses, and the
// compiler would fuse other multiply-adds: recording would change the run's
// round-off). Each contact k writes only its
// own history, flag and log slot, and every particle's sum is made in slot
// order, so the results are bit-identical whatever the team.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/contact_state.hpp"
#include "contact/rolling.hpp"
#include "core/particles.hpp"
#include "hooks/contact_log.hpp"
#include "kernel/buckets.hpp"
#include "kernel/pair_batch.hpp"
#include "kernel/pair_batch_2d.hpp"
#include "kernel/pruned_lists.hpp"
#include "kernel/team.hpp"
#include "kernel/thread_ranges.hpp"
#include "neighbor/cell_grid.hpp"

namespace granule {

// What the pair kernel reads and writes of the engine in one step.
template <int D>
struct PairStep {
  Particles<D>& particles;  // reads the state, adds to force_torque
  double dt;
  Periodicity periodic;
  std::uint8_t* in_contact;  // the bucket's per-slot flags (0: history cleared)
  ContactLog<D>* log;        // the contact log on a step that records one, else null
  int team;                  // threads (ThreadPolicy::pair_team)
  bool batched;              // the batched force pass where the model has one
  bool pruning;              // pruned lists on
  bool prune_due;            // particles may have closed the prune distance: note afresh
  double prune_distance;     // m
};

// What the pair kernel tells the engine: summed over the buckets of a step.
struct PairTally {
  std::int64_t touching = 0;    // contacts
  std::int64_t batched = 0;     // of which by the batched pass
  std::int64_t visited = 0;     // candidates the listing passes visited
  std::int64_t prunes = 0;      // notes of the pruned lists
  std::int64_t rebalances = 0;  // moves of the thread ranges
  double max_ratio = 0;         // deepest overlap / smaller radius
  double scatter_seconds = 0;   // keeping the sums in slot order (shared marks, deferred sums)
  double wait_seconds = 0;      // thread-seconds spent waiting at the barrier
};

template <int D, typename M>
class PairKernel {
 public:
  // Whether a step with batches on (PairStep::batched) takes the model's
  // batched force pass: where it has force_batch in this dimension
  // (contact_batch.hpp). The engine's count of batched contacts asks the same.
  static constexpr bool takes_batch(bool batches_on) {
    return has_force_batch<M, D>::value && batches_on;
  }

  template <bool Observed>
  void run(PairBucket<D, M>& bucket, const std::vector<typename M::Params>& params,
           const PairStep<D>& step, PairTally& tally);

  // The bucket's candidates were listed anew (`old` of them before, `fresh` now).
  void on_new_list(std::size_t old, std::size_t fresh) {
    ranges_.on_new_list(old, fresh);
    pruned_.on_new_list();
  }

 private:
  // Contacts ahead whose history and velocities the force pass asks the cache for.
  static constexpr std::size_t prefetch_distance = 16;
  // The listing pass runs ~3x faster per entry than the force pass: it fetches
  // further ahead (force and torque share a line, so few lines are in flight
  // per contact).
  static constexpr std::int64_t pass1_prefetch_distance = 64;
  static constexpr std::int64_t prefetch_min_candidates = 1 << 16;
  // Candidates per block: its listing pass, then its force pass while the
  // block's data are in the caches (~300 contacts in the dense box).
  static constexpr std::int64_t pair_block = 2048;
  // The listing pass: over all candidates, the same noting those near enough
  // to keep (pruning), or over the noted ones only.
  static constexpr int full_pass = 0, note_pass = 1, near_pass = 2;

  ThreadRanges<D> ranges_;
  PrunedLists pruned_;
};

template <int D, typename M>
template <bool Observed>
void PairKernel<D, M>::run(PairBucket<D, M>& b, const std::vector<typename M::Params>& params,
                           const PairStep<D>& step, PairTally& tally) {
  using History = typename M::template History<D>;
  using V = Vec<D>;
  using S = Spin<D>;
  using Deferred = typename ThreadRanges<D>::Deferred;
  using Clock = std::chrono::steady_clock;
  const std::int64_t count = static_cast<std::int64_t>(b.size());
  std::int64_t touching = 0;
  double max_ratio = 0;
  const int team = step.team;
  b.touched.resize(team);
  constexpr bool batchable = has_force_batch<M, D>::value;
  const bool batched = takes_batch(step.batched);
  if (b.law == -2) {  // once per list: do all candidates share one law (no index to load)?
    b.law = count ? static_cast<std::int64_t>(b.slot[0]) : -1;
    for (const std::uint32_t s : b.slot)
      if (s != b.slot[0]) b.law = -1;
  }
  Particles<D>& p = step.particles;
  const std::size_t n = p.size();
  ThreadRanges<D>& ranges = ranges_;
  if (team > 1) tally.scatter_seconds += ranges.prepare(team, count, n, b.i.data(), b.j.data());
  // Lists of threads that do not run this step (below) must not name old contacts.
  for (auto& list : b.touched) list.count = 0;
  const PrunedLists::Plan prune =
      pruned_.plan(step.pruning && count > 0, step.prune_due, team, ranges.split);
  const bool note_near = prune.note, use_near = prune.use;
  tally.visited += pruned_.visited(prune, count);
  const double prune_distance_m = step.prune_distance;
  ContactLog<D>* const log = step.log;
  double scatter_seconds = 0, wait_seconds = 0;
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
    if (t == 0) ranges.ran_team = static_cast<int>(nt);
    const double dt = step.dt;
    const std::uint32_t* const bi = b.i.data();
    const std::uint32_t* const bj = b.j.data();
    const std::uint32_t* const bslot = b.slot.data();
    History* const hist = b.history.data();
    const typename M::Params* const par_of = params.data();
    const bool one_law = b.law >= 0;
    // The shared law's parameters, or null: a local, not reloaded from the bucket per contact.
    const typename M::Params* const shared_law = one_law ? &par_of[b.law] : nullptr;
    const V* const x = p.position.data();
    const V* const v = p.velocity.data();
    const S* const w = p.spin.data();
    const double* const radius = p.radius.data();
    const double* const inv_mass = p.inv_mass.data();
    std::uint8_t* const in_contact = step.in_contact;
    ForceTorque<D>* const load = p.force_torque.data();
    const std::uint8_t* const shared = sharing ? ranges.shared.data() : nullptr;
    std::vector<Deferred>* const deferred = sharing ? &ranges.deferred[t] : nullptr;
    if (deferred) deferred->clear();
    const Periodicity periodic = step.periodic;
    const bool periodic_on = periodic.on();
    const int periodic_axis = periodic_on ? periodic.axis : 0;
    const std::size_t offset = b.offset;
    std::int64_t touching = 0;
    double max_ratio = 0;
    const auto started = sharing ? Clock::now() : Clock::time_point{};  // for rebalance()
    const std::int64_t begin = sharing ? ranges.split[t] : 0,
                       end = sharing ? ranges.split[t + 1] : count;
    StepList<D>& list = b.touched[t];
    list.start(static_cast<std::size_t>(end - begin));
    // The list's array and count in registers.
    std::uint32_t* const listing = list.entries.data();
    std::size_t listed = 0;
    // Pruning: this thread's noted candidates, written on a noting step, read
    // on the others (not when OpenMP gave a smaller team: then the ranges differ).
    const bool noting = note_near && nt == team, near_only = use_near && nt == team;
    HotArray<std::uint32_t>* const near = noting || near_only ? &pruned_.of_thread(t) : nullptr;
    if (noting) near->resize(static_cast<std::size_t>(end - begin));
    std::uint32_t* const noted_out = noting ? near->data() : nullptr;
    const std::uint32_t* const near_in = near_only ? near->data() : nullptr;
    const std::int64_t near_count = near_only ? static_cast<std::int64_t>(near->size()) : 0;
    std::size_t noted = 0;
    // Small scenes live in the caches, where prefetching only costs.
    const bool prefetch = count >= prefetch_min_candidates;
    // The batch reads the masses only on a contact's first step (batch_needs_mass).
    const bool fetch_masses = !batched;
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
        const typename M::Params& par = one_law ? *shared_law : par_of[bslot[k]];
        in_contact[k] = 1;
        ContactState<D> c;
        c.dt = dt;
        // Coincident centres: any direction is as good as another, but it must be finite.
        c.normal = dist > 0 ? V(d * inv_dist) : V(V::UnitX());
        c.overlap = overlap;
        const V v_rel = v[j] - v[i];
        c.normal_velocity = v_rel.dot(c.normal);
        // Eq. 3.10: tangential slip of j's surface relative to i's, at the
        // contact point where the torques below apply the force (levers r - a/2):
        // the work the spring and dashpot take is then the work the particles give.
        const double lever_i = radius[i] - 0.5 * overlap, lever_j = radius[j] - 0.5 * overlap;
        c.tangential_velocity = v_rel - c.normal * c.normal_velocity +
                                Dim<D>::spin_cross(lever_i * w[i] + lever_j * w[j], c.normal);
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
        S torque_i = -lever_i * n_cross_t;
        S torque_j = -lever_j * n_cross_t;
        if constexpr (has_rolling<M>::value) {  // rolling resistance (rolling.hpp): M on i, -M on j
          const double inertia =
              rolling_inertia(rolling_compliance(inv_mass[i], p.inv_inertia[i], radius[i]),
                              rolling_compliance(inv_mass[j], p.inv_inertia[j], radius[j]));
          const S roll = M::rolling_torque(par, h, c, f.normal, S(w[i] - w[j]), inertia,
                                           p.inv_inertia[i] + p.inv_inertia[j]);
          torque_i += roll;
          torque_j -= roll;
        }
        add(i, j, total, torque_i, torque_j);
        // The largest overlap / smaller radius, without a division per contact.
        const double r_min = std::min(radius[i], radius[j]);
        if (overlap > max_ratio * r_min) max_ratio = overlap / r_min;
        if (log) {  // at run time: see the top of this file
          const std::size_t s = offset + k;
          log->record(s, static_cast<std::int32_t>(i), static_cast<std::int32_t>(j), overlap,
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
      if (batched) {
        by_batch = true;
        PairBatch<D, M> batch;
        batch.c.dt = dt;
        // The batch as a local reference and the arrays by value: captured
        // by reference (this closure is not inlined), each would be reloaded
        // through the closure after every store of a result, and those loads
        // sit on the path of each lane's addresses (3-4 % of the 3D pair loop).
        auto flush = [&batch_captured = batch, &max_ratio, &touching, load, shared, in_contact,
                      hist, deferred, x, offset, log]() {
          PairBatch<D, M>& batch = batch_captured;
          batch.lanes_in();
          batch.pad();
          batch.geometry();
          M::force_batch(batch.params, batch.history, batch.c);
          batch.totals();
          batch.lanes_out();
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
              const V normal = batch.normal(l);
              log->record(offset + k, static_cast<std::int32_t>(i), static_cast<std::int32_t>(j),
                          overlap, batch.c.normal_force[l], batch.c.normal_velocity[l], normal,
                          batch.tangential_force(l),
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
            batch.params[l] = one_law ? shared_law : &par_of[bslot[k]];
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
      ranges.pace.seconds[t] += std::chrono::duration<double>(arrived - started).count();
      ranges.pace.candidates[t] += static_cast<double>(end - begin);
      ranges.pace.listed[t] += static_cast<double>(listed);
      // The deferred contributions, thread by thread (each in its range's
      // order): slot order. Each thread adds those to its own particles (shared_split).
#pragma omp barrier
      const auto deferred_start = Clock::now();
      const double waited = std::chrono::duration<double>(deferred_start - arrived).count();
#pragma omp atomic
      wait_seconds += waited;
      const std::uint32_t lo = ranges.shared_split[t], width = ranges.shared_split[t + 1] - lo;
      for (std::int64_t u = 0; u < nt; ++u)
        for (const Deferred& d : ranges.deferred[u])
          if (d.particle - lo < width) {
            load[d.particle].force += d.force;
            load[d.particle].torque += d.torque;
          }
      if (t == 0)  // only thread 0 writes
        scatter_seconds += std::chrono::duration<double>(Clock::now() - deferred_start).count();
    }
    touching_out += touching;
    if (max_ratio > max_ratio_out) max_ratio_out = max_ratio;
  };
  run_on_team(team, work, touching, max_ratio);
  if (note_near) {
    pruned_.noted(team, ranges.ran_team, ranges.split, count);
    ++tally.prunes;
  }
  if (team > 1 && ranges.ran_team == team &&
      ranges.rebalance(team, count, n, b.i.data(), b.j.data(), b.touched, scatter_seconds))
    ++tally.rebalances;
  tally.scatter_seconds += scatter_seconds;
  tally.wait_seconds += wait_seconds;
  tally.touching += touching;
  if (batched) tally.batched += touching;
  if (max_ratio > tally.max_ratio) tally.max_ratio = max_ratio;
}

}  // namespace granule
