#include "parallel/distributed_run.hpp"

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/bytes.hpp"
#include "core/errors.hpp"

namespace granule::parallel {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using bytes::put;

template <typename T>
T take(const std::string& in, std::size_t& at) {
  return bytes::take<T>(in, at, "distributed run: a gathered record");
}

// Every rank's bytes, in rank order, on every rank.
std::string all_gather(const std::string& mine, MPI_Comm comm) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), at(static_cast<std::size_t>(size));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  std::size_t total = 0;
  for (int k = 0; k < size; ++k) {
    at[static_cast<std::size_t>(k)] = static_cast<int>(total);
    total += static_cast<std::size_t>(counts[static_cast<std::size_t>(k)]);
  }
  if (total > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw RunError(fmt::format("distributed run: {} bytes to gather at once", total));
  std::string all(total, '\0');
  MPI_Allgatherv(mine.data(), count, MPI_CHAR, all.data(), counts.data(), at.data(), MPI_CHAR,
                 comm);
  return all;
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
  if (sim_.is_periodic())
    throw InputError("distributed run: periodic scenes are not distributed yet");
  if (sim_.bond_counts().intact > 0)
    throw InputError("distributed run: parallel bonds are not distributed yet");
  if (!sim_.effects().diagnostics.empty() || sim_.hook_count() > 0)
    throw InputError(
        "distributed run: diagnostics and hooks are not distributed yet (their sums cross ranks)");
  // Canonical order makes each owned particle's sums independent of what else
  // its rank stores; prepare() (time step, skin, lists) sees the whole scene.
  sim_.set_canonical_order(true);
  sim_.ensure_prepared();
  sim_.set_external_rebuilds(true);
  reach_ = sim_.interaction_reach();
  // Every rank holds the whole scene now: the cut needs no communication, and
  // each keeps what its box holds.
  const std::vector<std::string> histories = sim_.pack_histories();
  cut(true);
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
  ghosts_ = exchange_ghosts(d_, reach_, owned_, comm_, plan_);
  install();
  times_.rebuild += since(t0);
}

template <int D>
void DistributedRun<D>::cut(bool whole_scene_here) {
  // Every rank's owned positions and ids; at construction every rank holds
  // the whole scene, so its own list is everyone's.
  const Particles<D>& p = sim_.share();
  std::vector<Vec<D>> points;
  std::vector<std::int64_t> ids;
  if (whole_scene_here) {
    for (std::size_t k = 0; k < p.size(); ++k)
      points.push_back(p.position[k]), ids.push_back(p.id[k]);
  } else {
    std::string mine;
    for (const auto& r : owned_) {
      put(mine, r.id);
      for (int a = 0; a < D; ++a) put(mine, r.position[a]);
    }
    const std::string all = all_gather(mine, comm_);
    for (std::size_t at = 0; at < all.size();) {
      ids.push_back(take<std::int64_t>(all, at));
      Vec<D> x;
      for (int a = 0; a < D; ++a) x[a] = take<double>(all, at);
      points.push_back(x);
    }
  }
  Box<D> domain;
  if (!points.empty()) {
    domain.lo = domain.hi = points[0];
    for (const auto& x : points)
      domain.lo = domain.lo.cwiseMin(x), domain.hi = domain.hi.cwiseMax(x);
  }
  // Half the reach beyond the outermost centres: a box's edge never sits on one.
  for (int a = 0; a < D; ++a) domain.lo[a] -= 0.5 * reach_, domain.hi[a] += 0.5 * reach_;
  d_ = bisect<D>(domain, {}, size_, points, {}, ids);
  // Particles leave the box the cut was made in (a drum's charge spreads, a
  // jet flies off): the outer faces reach to infinity, so that the ghosts a
  // rank gets are those within reach of all the space it owns, which is what
  // owner() gives it (the half-spaces of the cut tree).
  const double infinity = std::numeric_limits<double>::infinity();
  for (auto& box : d_.boxes)
    for (int a = 0; a < D; ++a) {
      if (box.lo[a] == domain.lo[a]) box.lo[a] = -infinity;
      if (box.hi[a] == domain.hi[a]) box.hi[a] = infinity;
    }
}

template <int D>
void DistributedRun<D>::take_records() {
  const std::vector<std::string> histories = sim_.pack_histories();
  const Particles<D>& p = sim_.share();
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    ParticleRecord<D>& r = owned_[k];
    r.position = p.position[k], r.velocity = p.velocity[k], r.spin = p.spin[k];
    r.payload = histories[k];
  }
}

template <int D>
void DistributedRun<D>::redistribute() {
  if (size_ == 1) {
    // One rank: no ghosts (no periodic images: refused), no migration, the
    // boxes never re-cut; the lists as the plain step rebuilds them.
    sim_.rebuild_share_lists();
    return;
  }
  take_records();
  // Re-cut when the largest share has grown past the threshold over the mean.
  std::int64_t mine = static_cast<std::int64_t>(owned_.size()), most = 0, total = 0;
  MPI_Allreduce(&mine, &most, 1, MPI_INT64_T, MPI_MAX, comm_);
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, comm_);
  if (total > 0 && static_cast<double>(most) * size_ > threshold_ * static_cast<double>(total) &&
      size_ > 1) {
    cut(false);
    ++recuts_;
  }
  migrated_ += static_cast<std::int64_t>(migrate(d_, owned_, comm_));
  ghosts_ = exchange_ghosts(d_, reach_, owned_, comm_, plan_);
  install();
}

template <int D>
void DistributedRun<D>::install() {
  const Particles<D>& old = sim_.share();
  Particles<D> share;
  share.next_id = old.next_id;
  share.index_of_id.assign(static_cast<std::size_t>(old.next_id), -1);
  std::vector<std::string> histories;
  histories.reserve(owned_.size());
  auto add = [&](const ParticleRecord<D>& r, bool ghost) {
    if (r.id < 0 || r.id >= share.next_id || share.index_of_id[r.id] >= 0)
      throw RunError(
          fmt::format("distributed run: rank {} received particle {} twice", rank_, r.id));
    share.index_of_id[r.id] = static_cast<std::int32_t>(share.size());
    share.position.push_back(r.position);
    share.velocity.push_back(r.velocity);
    share.spin.push_back(r.spin);
    share.force_torque.push_back({});
    share.radius.push_back(r.radius);
    share.mass.push_back(r.mass);
    share.inv_mass.push_back(r.inv_mass);
    share.inv_inertia.push_back(r.inv_inertia);
    share.id.push_back(r.id);
    share.material.push_back(r.material);
    share.fixed.push_back(static_cast<std::uint8_t>(ghost ? r.fixed | Simulation<D>::ghost_flag
                                                          : r.fixed & ~Simulation<D>::ghost_flag));
  };
  for (auto& r : owned_) {
    add(r, false);
    histories.push_back(std::move(r.payload));
    r.payload.clear();
  }
  for (const auto& g : ghosts_) add(g, true);
  sim_.install_share(std::move(share), histories);
}

template <int D>
void DistributedRun<D>::forward() {
  Particles<D>& p = sim_.share();
  // Only the records some rank holds a ghost of are read by the forward.
  for (const auto& to_rank : plan_.send)
    for (const auto& send : to_rank) {
      ParticleRecord<D>& r = owned_[send.index];
      r.position = p.position[send.index], r.velocity = p.velocity[send.index];
      r.spin = p.spin[send.index];
    }
  forward_ghosts(d_, plan_, owned_, ghosts_, comm_);
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
  for (std::int64_t s = 0; s < steps; ++s) {
    auto t0 = Clock::now();
    // One rank's rule, over every rank: rebuild when any particle anywhere moved
    // half the skin.
    int due = sim_.lists_due() ? 1 : 0, any = 0;
    MPI_Allreduce(&due, &any, 1, MPI_INT, MPI_MAX, comm_);
    auto t1 = Clock::now();
    times_.waiting += std::chrono::duration<double>(t1 - t0).count();
    if (any) {
      redistribute();
      ++times_.rebuilds;
    } else {
      forward();
    }
    auto t2 = Clock::now();
    (any ? times_.rebuild : times_.exchange) += std::chrono::duration<double>(t2 - t1).count();
    sim_.step();
    times_.compute += since(t2);
  }
}

template <int D>
std::vector<GatheredParticle<D>> DistributedRun<D>::gather() const {
  const Particles<D>& p = sim_.share();
  std::string mine;
  for (std::size_t k = 0; k < owned_.size(); ++k) {
    put(mine, p.id[k]);
    put(mine, p.position[k]);
    put(mine, p.velocity[k]);
    put(mine, p.spin[k]);
    put(mine, p.force_torque[k].force);
    put(mine, p.force_torque[k].torque);
  }
  const std::string all = all_gather(mine, comm_);
  std::vector<GatheredParticle<D>> out;
  for (std::size_t at = 0; at < all.size();) {
    GatheredParticle<D> g;
    g.id = take<std::int64_t>(all, at);
    g.position = take<Vec<D>>(all, at);
    g.velocity = take<Vec<D>>(all, at);
    g.spin = take<Spin<D>>(all, at);
    g.force = take<Vec<D>>(all, at);
    g.torque = take<Spin<D>>(all, at);
    out.push_back(g);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

template <int D>
std::int64_t DistributedRun<D>::global_particles() const {
  std::int64_t mine = static_cast<std::int64_t>(owned_.size()), total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_INT64_T, MPI_SUM, comm_);
  return total;
}

template <int D>
std::string DistributedRun<D>::describe() const {
  return fmt::format("ranks: {}, {}", size_, d_.describe());
}

template class DistributedRun<2>;
template class DistributedRun<3>;

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
