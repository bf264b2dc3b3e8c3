#include "parallel/distributed_run.hpp"

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/bytes.hpp"
#include "core/errors.hpp"
#include "parallel/gathering.hpp"

namespace granule::parallel {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using bytes::put;

// Appends record r to `to` with the given `fixed` flags and load; refuses an id
// that is out of range or already there (`what` names the occasion).
template <int D>
void append(Particles<D>& to, const ParticleRecord<D>& r, std::uint8_t fixed,
            const ForceTorque<D>& load, const char* what) {
  if (r.id < 0 || r.id >= to.next_id || to.index_of_id[r.id] >= 0)
    throw RunError(fmt::format("distributed run: {} particle {} twice", what, r.id));
  to.index_of_id[r.id] = static_cast<std::int32_t>(to.size());
  to.position.push_back(r.position);
  to.velocity.push_back(r.velocity);
  to.spin.push_back(r.spin);
  to.force_torque.push_back(load);
  to.radius.push_back(r.radius);
  to.mass.push_back(r.mass);
  to.inv_mass.push_back(r.inv_mass);
  to.inv_inertia.push_back(r.inv_inertia);
  to.id.push_back(r.id);
  to.material.push_back(r.material);
  to.fixed.push_back(fixed);
}

}  // namespace

template <int D>
DistributedRun<D>::DistributedRun(Simulation<D>& sim, MPI_Comm comm, double rebalance_threshold)
    : sim_(sim), comm_(comm), threshold_(rebalance_threshold) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (!(threshold_ >= 1))
    throw InputError(fmt::format(
        "distributed run: rebalance threshold {} (the largest share over the mean, 1 or more)",
        threshold_));
  if (!sim_.effects().diagnostics.empty() && !sim_.hooks_wrapped())
    throw InputError(
        "distributed run: diagnostics would see only this rank's share; take the steps they "
        "observe on the whole scene (Simulation::whole_step_due, parallel/scene_over_ranks.hpp)");
  if (sim_.hook_count() > 0 && !sim_.hooks_wrapped())
    throw InputError(
        "distributed run: hooks would see only this rank's share; fire them on the gathered "
        "scene (Simulation::set_hook_wrapper, parallel/scene_over_ranks.hpp)");
  // Canonical order makes each owned particle's sums independent of what else
  // its rank stores; prepare() (time step, skin, lists) sees the whole scene.
  sim_.set_canonical_order(true);
  sim_.ensure_prepared();
  // A script's removals left the lists naming moved storage indices: built
  // anew (histories carried by id) before they are packed below.
  sim_.renew_lists_if_indices_stale();
  sim_.set_external_rebuilds(true);
  sim_.set_holds_share(size_ > 1);
  sim_.set_keep_wall_reactions(true);
  // The bonds of particles a script removed break now, on the whole scene, as
  // the next step would break them (no rank can tell a removed particle from
  // another rank's).
  sim_.break_orphan_bonds();
  contact_reach_ = sim_.interaction_reach();
  reach_ = std::max(contact_reach_, sim_.led_bond_reach());
  // Each rank's scene wraps the periodic axis itself (minimum images): a
  // ghost is needed once per rank, and only while the reach is under half
  // the period (beyond it a particle would meet two images of another).
  const Periodicity& periodic = sim_.periodicity();
  if (periodic.on() && !(2 * reach_ < periodic.length))
    throw InputError(fmt::format(
        "distributed run: the periodic length {} m along axis {} is not more than twice the "
        "interaction reach ({} m: the largest diameter, the skin and any adhesive reach, or "
        "the longest parallel bond); lengthen the period or run on one process",
        periodic.length, "xyz"[periodic.axis], reach_));
  // Every rank holds the whole scene now: the cut needs no communication, and
  // each keeps what its box holds. The last step's contacts are kept for a
  // gather before any step on the shares.
  const std::vector<std::string> histories = sim_.pack_histories();
  whole_contacts_ = sim_.pack_led_contacts();
  cut(stored_costs(sim_.share().size()), true);
  Particles<D>& p = sim_.share();
  owned_.clear();
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (d_.owner(p.position[k]) != rank_) continue;
    ParticleRecord<D> r;
    r.id = p.id[k];
    r.position = p.position[k], r.velocity = p.velocity[k], r.spin = p.spin[k];
    r.radius = p.radius[k], r.mass = p.mass[k];
    r.inv_mass = p.inv_mass[k], r.inv_inertia = p.inv_inertia[k];
    r.material = p.material[k], r.fixed = p.fixed[k];
    r.payload = histories[k];
    owned_.push_back(std::move(r));
  }
  std::sort(owned_.begin(), owned_.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  const auto t0 = Clock::now();
  ghosts_ = exchange_ghosts(d_, reach_, owned_, comm_, plan_, Images::wrapped);
  shared_ = std::make_unique<SharedForward<D>>(comm_);
  if (shared_->usable()) shared_->fit(plan_, step_maxima);
  install();
  // Last, past every check that can throw: a scene left by a refused run keeps ending
  // the grace itself.
  sim_.set_external_overlap_grace(true);
  times_.rebuild += since(t0);
}

template <int D>
std::vector<double> DistributedRun<D>::stored_costs(std::size_t count) const {
  const std::vector<std::uint32_t> contacts = sim_.contacts_per_particle();
  std::vector<double> cost(count);
  for (std::size_t k = 0; k < count; ++k) cost[k] = particle_cost(contacts[k]);
  return cost;
}

template <int D>
void DistributedRun<D>::cut(const std::vector<double>& cost, bool whole_scene_here) {
  // Every rank's owned positions, ids and costs; at construction every rank
  // holds the whole scene, so its own list is everyone's.
  const Particles<D>& p = sim_.share();
  std::vector<Vec<D>> points;
  std::vector<std::int64_t> ids;
  std::vector<double> weights;
  if (whole_scene_here) {
    for (std::size_t k = 0; k < p.size(); ++k)
      points.push_back(p.position[k]), ids.push_back(p.id[k]);
    weights = cost;
  } else {
    std::string mine;
    for (std::size_t k = 0; k < owned_.size(); ++k) {
      put(mine, owned_[k].id);
      for (int a = 0; a < D; ++a) put(mine, owned_[k].position[a]);
      put(mine, cost[k]);
    }
    const std::string all = all_gather(mine, comm_);
    for (std::size_t at = 0; at < all.size();) {
      ids.push_back(take_gathered<std::int64_t>(all, at));
      Vec<D> x;
      for (int a = 0; a < D; ++a) x[a] = take_gathered<double>(all, at);
      points.push_back(x);
      weights.push_back(take_gathered<double>(all, at));
    }
  }
  Box<D> domain;
  if (!points.empty()) {
    domain.lo = domain.hi = points[0];
    for (const auto& x : points)
      domain.lo = domain.lo.cwiseMin(x), domain.hi = domain.hi.cwiseMax(x);
  }
  // Half the reach beyond the outermost centres: a box's edge never sits on one.
  // A scene with no particles yet (a feeder's), or none that can touch, still
  // gets a box of some size to cut; its outer faces go to infinity below.
  for (int a = 0; a < D; ++a) {
    domain.lo[a] -= 0.5 * reach_, domain.hi[a] += 0.5 * reach_;
    if (!(domain.hi[a] > domain.lo[a])) domain.lo[a] -= 0.5, domain.hi[a] += 0.5;
  }
  // A periodic axis: the domain is the period, where the scene keeps every centre.
  const Periodicity& periodic = sim_.periodicity();
  std::array<bool, D> wraps{};
  if (periodic.on()) {
    wraps[periodic.axis] = true;
    domain.lo[periodic.axis] = periodic.origin;
    domain.hi[periodic.axis] = periodic.origin + periodic.length;
  }
  d_ = bisect<D>(domain, wraps, size_, points, weights, ids);
  // Particles leave the box the cut was made in (a drum's charge spreads, a
  // jet flies off): the outer faces reach to infinity, so that the ghosts a
  // rank gets are those within reach of all the space it owns, which is what
  // owner() gives it (the half-spaces of the cut tree).
  const double infinity = std::numeric_limits<double>::infinity();
  for (auto& box : d_.boxes)
    for (int a = 0; a < D; ++a) {
      if (wraps[a]) continue;
      if (box.lo[a] == domain.lo[a]) box.lo[a] = -infinity;
      if (box.hi[a] == domain.hi[a]) box.hi[a] = infinity;
    }
}

template <int D>
void DistributedRun<D>::take_states() {
  const Particles<D>& p = sim_.share();
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    ParticleRecord<D>& r = owned_[k];
    r.position = p.position[k], r.velocity = p.velocity[k], r.spin = p.spin[k];
  }
}

template <int D>
void DistributedRun<D>::take_histories(const std::vector<std::uint8_t>* only) {
  std::vector<std::string> histories = sim_.pack_histories(only);
  for (std::size_t k = 0; k < owned_.size(); ++k) owned_[k].payload = std::move(histories[k]);
}

template <int D>
void DistributedRun<D>::redistribute() {
  if (size_ == 1) {
    // One rank: no ghosts (the scene wraps its periodic axis), no migration, the
    // boxes never re-cut; the lists as the plain step rebuilds them.
    sim_.rebuild_share_lists();
    return;
  }
  // The states now; the histories below, once it is known who leaves.
  take_states();
  sync_bonds();
  // Re-cut when the costliest share has grown past the threshold over the mean
  // (the shares' costs summed in a fixed order, so every rank decides alike).
  const std::vector<double> cost = stored_costs(owned_.size());
  double mine = 0;
  for (const double c : cost) mine += c;
  std::vector<double> shares(static_cast<std::size_t>(size_));
  MPI_Allgather(&mine, 1, MPI_DOUBLE, shares.data(), 1, MPI_DOUBLE, comm_);
  double most = 0, total = 0;
  for (const double c : shares) most = std::max(most, c), total += c;
  if (total > 0 && most * size_ > threshold_ * total) {
    cut(cost, false);
    ++recuts_;
    ++times_.recuts;
  }
  // Only the particles leaving this rank pack their contacts' histories; the
  // staying ones' stay in the lists, which install_share carries from.
  std::vector<std::uint8_t> leaving(owned_.size(), 0);
  bool any_leaving = false;
  for (std::size_t k = 0; k < owned_.size(); ++k)
    if (d_.owner(owned_[k].position) != rank_) leaving[k] = 1, any_leaving = true;
  if (any_leaving) take_histories(&leaving);
  migrated_ += static_cast<std::int64_t>(migrate(d_, owned_, comm_));
  ghosts_ = exchange_ghosts(d_, reach_, owned_, comm_, plan_, Images::wrapped);
  if (shared_ && shared_->usable()) shared_->fit(plan_, step_maxima);
  install(true);
}

template <int D>
void DistributedRun<D>::sync_bonds() {
  if (sim_.bonds().empty()) return;
  sim_.set_bond_states(all_gather(sim_.pack_led_bonds(), comm_));
  // A bond's partner must be a ghost of its owner's rank until the next
  // rebuild: the ghosts' reach covers the longest bond now (a bond stretches
  // between rebuilds, but the ghosts chosen now stay).
  double mine = sim_.led_bond_reach(), longest = 0;
  MPI_Allreduce(&mine, &longest, 1, MPI_DOUBLE, MPI_MAX, comm_);
  reach_ = std::max(contact_reach_, longest);
}

template <int D>
void DistributedRun<D>::install(bool keep_own) {
  const Particles<D>& old = sim_.share();
  Particles<D> share;
  share.next_id = old.next_id;
  share.index_of_id.assign(static_cast<std::size_t>(old.next_id), -1);
  std::vector<std::string> histories;
  histories.reserve(owned_.size());
  const std::string what = fmt::format("rank {} received", rank_);
  auto add = [&](const ParticleRecord<D>& r, bool ghost) {
    const std::uint8_t flags =
        ghost ? r.fixed | Simulation<D>::ghost_flag : r.fixed & ~Simulation<D>::ghost_flag;
    append(share, r, flags, ForceTorque<D>{}, what.c_str());
  };
  for (auto& r : owned_) {
    add(r, false);
    histories.push_back(std::move(r.payload));
    r.payload.clear();
  }
  for (const auto& g : ghosts_) add(g, true);
  sim_.install_share(std::move(share), histories, keep_own);
  steps_since_install_ = 0;
}

template <int D>
void DistributedRun<D>::forward(double* maxima, int count) {
  Particles<D>& p = sim_.share();
  // Only the records some rank holds a ghost of are read by the forward.
  for (const auto& to_rank : plan_.send)
    for (const auto& send : to_rank) {
      ParticleRecord<D>& r = owned_[send.index];
      r.position = p.position[send.index], r.velocity = p.velocity[send.index];
      r.spin = p.spin[send.index];
    }
  if (shared_ && shared_->usable())
    shared_->forward(d_, plan_, owned_, ghosts_, maxima, count);
  else
    forward_ghosts(d_, plan_, owned_, ghosts_, comm_, maxima, count);
  const std::size_t first = owned_.size();
  for (std::size_t g = 0; g < ghosts_.size(); ++g) {
    p.position[first + g] = ghosts_[g].position;
    p.velocity[first + g] = ghosts_[g].velocity;
    p.spin[first + g] = ghosts_[g].spin;
  }
}

template <int D>
void DistributedRun<D>::advance(std::int64_t steps) {
  if (steps < 0)
    throw InputError(fmt::format("cannot advance a negative number of steps ({})", steps));
  if (dissolved_) throw RunError("distributed run: a step after the scene was gathered");
  for (std::int64_t s = 0; s < steps; ++s) {
    auto t0 = Clock::now();
    // One rank's rule, over every rank: rebuild when any particle anywhere moved
    // half the skin. With it the fastest speed anywhere in the last step, for
    // the pruned lists' travel (a ghost moves as fast as its owner lets it).
    // And whether any rank notes its pruned lists this step, so that all do.
    const double mine[step_maxima] = {sim_.lists_due() ? 1.0 : 0.0, sim_.last_fastest_speed_sq(),
                                      sim_.prune_due_next() ? 1.0 : 0.0,
                                      sim_.last_pair_overlap_ratio(),
                                      sim_.last_placed_pair_ratio()};
    double anywhere[step_maxima] = {mine[0], mine[1], mine[2], mine[3], mine[4]};
    // Few ranks: the ghosts' states sent at once, with the flag and the speed
    // (wasted on a rebuild step, which sends them again).
    const bool folded = size_ > 1 && size_ <= fold_ranks;
    if (folded)
      forward(anywhere, step_maxima);
    else
      MPI_Allreduce(mine, anywhere, step_maxima, MPI_DOUBLE, MPI_MAX, comm_);
    const bool any = anywhere[0] > 0;
    sim_.widen_prune_travel(anywhere[1]);
    sim_.note_pruned_lists_with(anywhere[2] > 0);
    sim_.end_overlap_grace_with(anywhere[3]);
    sim_.end_placed_grace_with(anywhere[4]);
    auto t1 = Clock::now();
    (folded ? times_.exchange : times_.waiting) += std::chrono::duration<double>(t1 - t0).count();
    if (any) {
      redistribute();
      ++times_.rebuilds;
    } else if (!folded) {
      forward();
    }
    auto t2 = Clock::now();
    (any ? times_.rebuild : times_.exchange) += std::chrono::duration<double>(t2 - t1).count();
    // Counted before the step: its hooks fire inside it, after its contacts.
    ++steps_since_install_;
    sim_.step();
    times_.compute += since(t2);
  }
}

template <int D>
void DistributedRun<D>::dissolve() {
  if (dissolved_) return;
  dissolved_ = true;
  const auto t0 = Clock::now();
  // The last step's verdict on the scene's overlaps, given before the whole scene
  // steps again (the next distributed step would have given it).
  double deepest[2] = {sim_.last_pair_overlap_ratio(), sim_.last_placed_pair_ratio()};
  MPI_Allreduce(MPI_IN_PLACE, deepest, 2, MPI_DOUBLE, MPI_MAX, comm_);
  sim_.end_overlap_grace_with(deepest[0]);
  sim_.end_placed_grace_with(deepest[1]);
  sim_.set_external_overlap_grace(false);
  take_records();
  sync_bonds();
  const Particles<D>& p = sim_.share();
  std::string mine;
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    pack(owned_[k], mine);
    put(mine, p.force_torque[k].force);
    put(mine, p.force_torque[k].torque);
  }
  // The last step's tallies and wall reactions (unless no step was taken on
  // the shares: the walls' are then still the whole scene's). Every rank has
  // taken the same steps.
  const bool stepped = steps_since_install_ > 0;
  const Tallies sum = sum_tallies(all_gather(tallies(sim_.counters()), comm_));
  const std::string all_reactions =
      all_gather(stepped ? sim_.pack_wall_reactions() : std::string(), comm_);
  const std::string all = all_gather(mine, comm_);
  // The last step's contacts (only where the scene records them: the same on every rank).
  const std::string all_contacts = !sim_.record_contacts() ? std::string()
                                   : stepped ? all_gather(sim_.pack_led_contacts(), comm_)
                                             : whole_contacts_;

  std::vector<ParticleRecord<D>> records;
  std::vector<ForceTorque<D>> loads;
  for (std::size_t at = 0; at < all.size();) {
    records.push_back(unpack<D>(all, at));
    ForceTorque<D> ft;
    ft.force = take_gathered<Vec<D>>(all, at);
    ft.torque = take_gathered<Spin<D>>(all, at);
    loads.push_back(ft);
  }
  std::vector<std::size_t> order(records.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return records[a].id < records[b].id; });
  Particles<D> whole;
  whole.next_id = p.next_id;
  whole.index_of_id.assign(static_cast<std::size_t>(whole.next_id), -1);
  std::vector<std::string> histories;
  histories.reserve(records.size());
  for (const std::size_t k : order) {
    ParticleRecord<D>& r = records[k];
    append(whole, r, static_cast<std::uint8_t>(r.fixed & ~Simulation<D>::ghost_flag), loads[k],
           "gathered");
    histories.push_back(std::move(r.payload));
  }

  // Each wall's reaction as one process sums it: from zero, minus each
  // contact's force on its particle, model by model and particle by particle
  // in id order (a particle's wall contacts are all on its owner's rank, in
  // the order one process lists them).
  struct Reaction {
    std::int32_t model = 0;
    std::int64_t id = 0;
    std::uint32_t wall = 0;
    Vec<D> force = Vec<D>::Zero();
    double axial = 0;
  };
  std::vector<Reaction> each;
  for (std::size_t at = 0; at < all_reactions.size();) {
    Reaction r;
    r.model = take_gathered<std::int32_t>(all_reactions, at);
    r.id = take_gathered<std::int64_t>(all_reactions, at);
    r.wall = take_gathered<std::uint32_t>(all_reactions, at);
    r.force = take_gathered<Vec<D>>(all_reactions, at);
    r.axial = take_gathered<double>(all_reactions, at);
    each.push_back(r);
  }
  std::stable_sort(each.begin(), each.end(), [](const Reaction& a, const Reaction& b) {
    return a.model != b.model ? a.model < b.model : a.id < b.id;
  });
  const std::size_t walls = static_cast<std::size_t>(sim_.wall_count());
  std::vector<Vec<D>> force(walls, Vec<D>::Zero());
  std::vector<double> axial(walls, 0.0);
  for (const Reaction& r : each) {
    if (r.wall >= walls)
      throw RunError(fmt::format("distributed run: a reaction on wall {} of {}", r.wall, walls));
    force[r.wall] -= r.force;
    axial[r.wall] -= r.axial;
  }
  sim_.set_external_rebuilds(false);
  sim_.set_holds_share(false);
  sim_.set_keep_wall_reactions(false);
  sim_.install_share(std::move(whole), histories);
  sim_.set_step_tallies(sum.pair_contacts, sum.pair_batched, sum.wall_contacts, sum.wall_batched,
                        sum.max_overlap_ratio);
  if (stepped) sim_.set_wall_reactions(force, axial);
  if (sim_.record_contacts()) sim_.set_gathered_contacts(all_contacts);
  owned_.clear();
  ghosts_.clear();
  times_.rebuild += since(t0);
}

template <int D>
std::string DistributedRun<D>::describe() const {
  if (size_ == 1) return fmt::format("ranks: {}, {}", size_, d_.describe());
  // How the ghosts' states travel each step (shared_forward.hpp).
  return fmt::format("ranks: {}, {}; ghosts by {}", size_, d_.describe(),
                     shared_ && shared_->usable() ? "shared memory" : "messages");
}

template class DistributedRun<2>;
template class DistributedRun<3>;

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
