// DistributedRun's answers about the whole scene while it stays shared
// (distributed_run.hpp): the step's tallies, stats()' totals, every
// particle's state, the particle count. Each is one gather over the ranks.
#include "parallel/distributed_run.hpp"

#ifdef GRANULE_HAVE_MPI

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <numeric>

#include "core/bytes.hpp"
#include "core/errors.hpp"
#include "parallel/gathering.hpp"

namespace granule::parallel {

using bytes::put;

template <int D>
std::string DistributedRun<D>::tallies(const GlobalStats& here) const {
  // No step since the shares were made: the scene's tallies are still the
  // whole scene's, on every rank (counted once, from rank 0).
  const bool stepped = steps_since_install_ > 0;
  std::string out;
  put(out, static_cast<std::int64_t>(owned_.size()));
  std::int64_t led_batched = 0;
  const std::int64_t led = stepped ? sim_.led_pair_contacts(&led_batched) : 0;
  put(out, stepped ? led : rank_ == 0 ? here.contacts_particle : 0);
  put(out, stepped ? led_batched : rank_ == 0 ? here.contacts_batched : 0);
  put(out, stepped || rank_ == 0 ? here.contacts_wall : std::int64_t{0});
  put(out, stepped || rank_ == 0 ? here.contacts_wall_batched : std::int64_t{0});
  put(out, here.max_overlap_ratio);
  return out;
}

template <int D>
GlobalStats DistributedRun<D>::totals() const {
  GlobalStats g = sim_.counters();  // time, step, this rank's counters
  // One message per rank, gathered at once: its tallies, then its owned
  // particles' ids and terms as Simulation::stats() forms them, a column each.
  const Particles<D>& p = sim_.share();
  TotalsBuffers& b = totals_buffers_;
  std::vector<std::uint32_t>& which = b.which;
  which.clear();
  for (std::size_t i = 0; i < owned_.size(); ++i)
    if (!p.fixed[i]) which.push_back(static_cast<std::uint32_t>(i));
  typename Simulation<D>::StatColumns& t = b.columns;
  sim_.stat_columns(which.data(), which.size(), t);
  std::array<const std::vector<double>*, D + 4> columns;
  columns[0] = &t.kinetic_translational, columns[1] = &t.kinetic_rotational;
  for (int a = 0; a < D; ++a) columns[2 + a] = &t.momentum[static_cast<std::size_t>(a)];
  columns[2 + D] = &t.angular_momentum_z;
  columns[3 + D] = &t.mass;
  const std::size_t n = which.size(), terms = columns.size();
  std::string& mine = b.mine;
  mine = tallies(g);
  put(mine, static_cast<std::int64_t>(n));
  std::size_t at = mine.size();
  mine.resize(at + n * (sizeof(std::int64_t) + terms * sizeof(double)));
  for (const std::uint32_t i : which) {
    std::memcpy(mine.data() + at, &p.id[i], sizeof(std::int64_t));
    at += sizeof(std::int64_t);
  }
  for (const auto* column : columns) {
    std::memcpy(mine.data() + at, column->data(), n * sizeof(double));
    at += n * sizeof(double);
  }
  all_gather(mine, comm_, b.all);
  const std::string& all = b.all;
  // Every rank's columns: id and term j of particle k at id[k] and term[j][k].
  Tallies sum;
  std::vector<std::int64_t>& id = b.id;
  std::vector<std::vector<double>>& term = b.term;
  id.clear();
  term.resize(terms);
  for (auto& column : term) column.clear();
  for (at = 0; at < all.size();) {
    add_tallies(sum, all, at);
    const auto count = take_gathered<std::int64_t>(all, at);
    const std::size_t row = sizeof(std::int64_t) + terms * sizeof(double);
    if (count < 0 || static_cast<std::size_t>(count) > (all.size() - at) / row)
      throw RunError(
          fmt::format("distributed run: {} particles' terms in a gathered record", count));
    const std::size_t c = static_cast<std::size_t>(count), first = id.size();
    id.resize(first + c);
    std::memcpy(id.data() + first, all.data() + at, c * sizeof(std::int64_t));
    at += c * sizeof(std::int64_t);
    for (auto& column : term) {
      column.resize(first + c);
      std::memcpy(column.data() + first, all.data() + at, c * sizeof(double));
      at += c * sizeof(double);
    }
  }
  // Summed in id order, as one process sums them. The ids are below next_id:
  // where they are dense (no scene removed most of its particles), each
  // particle goes to its id's place, which is linear, else they are sorted.
  const std::int64_t id_count = p.next_id;
  std::vector<std::int32_t>& order = b.order;  // indices into the columns, in id order
  order.clear();
  if (id_count <= 4 * static_cast<std::int64_t>(id.size()) + 64) {
    std::vector<std::int32_t>& at_id = b.at_id;
    at_id.assign(static_cast<std::size_t>(id_count), -1);
    for (std::size_t k = 0; k < id.size(); ++k) {
      if (id[k] < 0 || id[k] >= id_count)
        throw RunError(fmt::format("distributed run: particle id {} of {}", id[k], id_count));
      at_id[static_cast<std::size_t>(id[k])] = static_cast<std::int32_t>(k);
    }
    for (const std::int32_t k : at_id)
      if (k >= 0) order.push_back(k);
  } else {
    order.resize(id.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
      return id[static_cast<std::size_t>(a)] < id[static_cast<std::size_t>(b)];
    });
  }
  g.kinetic_translational = g.kinetic_rotational = g.angular_momentum_z = g.free_mass = 0;
  Vec<D> momentum = Vec<D>::Zero();
  for (const std::int32_t k : order) {
    g.kinetic_translational += term[0][static_cast<std::size_t>(k)];
    g.kinetic_rotational += term[1][static_cast<std::size_t>(k)];
    for (int a = 0; a < D; ++a)
      momentum[a] += term[2 + static_cast<std::size_t>(a)][static_cast<std::size_t>(k)];
    g.angular_momentum_z += term[2 + D][static_cast<std::size_t>(k)];
    g.free_mass += term[3 + D][static_cast<std::size_t>(k)];
  }
  g.momentum = Triple{};
  for (int a = 0; a < D; ++a) g.momentum[static_cast<std::size_t>(a)] = momentum[a];
  g.particles = sum.particles;
  g.contacts_particle = sum.pair_contacts;
  g.contacts_batched = sum.pair_batched;  // of the led pairs, as contacts_particle
  g.contacts_wall = sum.wall_contacts;
  g.contacts_wall_batched = sum.wall_batched;  // each wall contact is its particle's rank's
  g.max_overlap_ratio = sum.max_overlap_ratio;
  return g;
}

template <int D>
typename Simulation<D>::StateOverride DistributedRun<D>::gathered_state() const {
  constexpr int sc = Dim<D>::spin_components;
  typename Simulation<D>::StateOverride out;
  auto& s = out.state;
  for (const GatheredParticle<D>& g : gather()) {
    s.id.push_back(g.id);
    s.radius.push_back(g.radius);
    s.material.push_back(g.material);
    s.fixed.push_back(g.fixed);
    for (int a = 0; a < D; ++a) {
      s.position.push_back(g.position[a]);
      s.velocity.push_back(g.velocity[a]);
      out.force.push_back(g.force[a]);
    }
    if constexpr (sc == 1) {
      s.spin.push_back(g.spin);
      out.torque.push_back(g.torque);
    } else {
      for (int a = 0; a < sc; ++a) s.spin.push_back(g.spin[a]), out.torque.push_back(g.torque[a]);
    }
  }
  return out;
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
    put(mine, p.radius[k]);
    put(mine, p.material[k]);
    put(mine, static_cast<std::uint8_t>(p.fixed[k] & ~Simulation<D>::ghost_flag));
  }
  const std::string all = all_gather(mine, comm_);
  std::vector<GatheredParticle<D>> out;
  for (std::size_t at = 0; at < all.size();) {
    GatheredParticle<D> g;
    g.id = take_gathered<std::int64_t>(all, at);
    g.position = take_gathered<Vec<D>>(all, at);
    g.velocity = take_gathered<Vec<D>>(all, at);
    g.spin = take_gathered<Spin<D>>(all, at);
    g.force = take_gathered<Vec<D>>(all, at);
    g.torque = take_gathered<Spin<D>>(all, at);
    g.radius = take_gathered<double>(all, at);
    g.material = take_gathered<std::int32_t>(all, at);
    g.fixed = take_gathered<std::uint8_t>(all, at);
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

// The class is instantiated in distributed_run.cpp; here only the members defined here.
#define GRANULE_QUERIES(D)                                                                  \
  template std::string DistributedRun<D>::tallies(const GlobalStats&) const;                \
  template GlobalStats DistributedRun<D>::totals() const;                                   \
  template typename Simulation<D>::StateOverride DistributedRun<D>::gathered_state() const; \
  template std::vector<GatheredParticle<D>> DistributedRun<D>::gather() const;              \
  template std::int64_t DistributedRun<D>::global_particles() const;
GRANULE_QUERIES(2)
GRANULE_QUERIES(3)
#undef GRANULE_QUERIES

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
