// The kernels' candidate lists, built from the cell grid's pairs and the
// walls at each neighbour-list rebuild: one bucket per contact model (the
// pair table says which model a material pair uses), with each contact's
// history (and event tracking) carried over from the old lists by persistent
// id, so a rebuild or a re-sort changes nothing a contact remembers. Also the
// space-filling-curve order large scenes are kept in, and the canonical order
// (order_by_ids) that makes every particle's sums independent of storage.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>

#include "contact/pair_table.hpp"
#include "core/particles.hpp"
#include "geometry/mesh_set.hpp"
#include "geometry/walls.hpp"
#include "kernel/buckets.hpp"

namespace granule {

// Reorders `v` so that entry k is the old entry order[k]: the one permutation
// step of every re-sort here (particle storage, a bucket's candidates).
template <typename Array, typename Index>
void gather(Array& v, const std::vector<Index>& order) {
  const Array old = v;
  for (std::size_t k = 0; k < order.size(); ++k) v[k] = old[order[k]];
}

namespace lists_detail {
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
// `also(k, o)` carries whatever else an entry keeps.
template <typename Bucket, typename OwnerOf, typename PartnerOld, typename PartnerNew,
          typename Also = void (*)(std::size_t, std::uint32_t)>
void carry_history(
    const Bucket& old, Bucket& fresh, std::int64_t max_id, bool tracking, const OwnerOf& owner_ids,
    PartnerOld partner_old, PartnerNew partner_new, Also also = [](std::size_t, std::uint32_t) {}) {
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
        also(k, o);
        break;
      }
    }
  }
}
// Empties `bucket` for a new list and returns the old one. The step lists'
// storage only grows: the new bucket keeps it, emptied (it named the old
// candidates).
template <typename Bucket>
Bucket renew(Bucket& bucket) {
  Bucket old = std::move(bucket);
  bucket = Bucket{};
  bucket.touched = std::move(old.touched);
  for (auto& list : bucket.touched) list.count = 0;
  return old;
}
}  // namespace lists_detail

// The canonical order of a bucket's candidates: by (id_i, id_j), id_i < id_j.
// Particle p's contacts are then added to it in the order of their lower and
// higher ids whatever the storage order, so its sums are too (and a rank that
// stores the particles its own way can reproduce them). Counting by id_i, each
// particle's few partners then sorted by id_j: linear in the candidates and ids.
template <int D, typename M>
void order_by_ids(PairBucket<D, M>& b, std::int64_t id_count) {
  const std::size_t count = b.size();
  std::vector<std::uint32_t> start(static_cast<std::size_t>(id_count) + 1, 0);
  for (const std::int64_t a : b.id_i) ++start[static_cast<std::size_t>(a) + 1];
  for (std::size_t a = 1; a < start.size(); ++a) start[a] += start[a - 1];
  std::vector<std::uint32_t> order(count);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < count; ++k)
      order[fill[static_cast<std::size_t>(b.id_i[k])]++] = static_cast<std::uint32_t>(k);
  }
  for (std::size_t a = 0; a + 1 < start.size(); ++a)
    std::sort(order.begin() + start[a], order.begin() + start[a + 1],
              [&](std::uint32_t x, std::uint32_t y) { return b.id_j[x] < b.id_j[y]; });
  gather(b.i, order), gather(b.j, order), gather(b.slot, order);
  gather(b.id_i, order), gather(b.id_j, order);
}

// Replaces `bucket` (model `model` of the pair table) by the candidate pairs
// of that model, histories carried over; `canonical`: in order_by_ids's order.
// Returns the old bucket's size.
template <int D, typename M>
std::size_t list_pairs(PairBucket<D, M>& bucket, int model, const Particles<D>& p,
                       const PairTable& pairs,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>& candidates,
                       bool tracking, bool canonical) {
  using B = PairBucket<D, M>;
  B old = lists_detail::renew(bucket);
  B& fresh = bucket;
  const std::size_t expect = old.size() + old.size() / 8;
  fresh.i.reserve(expect), fresh.j.reserve(expect), fresh.slot.reserve(expect);
  fresh.id_i.reserve(expect), fresh.id_j.reserve(expect);
  for (auto [a, b] : candidates) {
    if (p.id[a] > p.id[b]) std::swap(a, b);
    const PairTable::Entry& e = pairs.at(p.material[a], p.material[b]);
    if (e.model != model) continue;
    fresh.i.push_back(a);
    fresh.j.push_back(b);
    fresh.slot.push_back(static_cast<std::uint32_t>(e.slot));
    fresh.id_i.push_back(p.id[a]);
    fresh.id_j.push_back(p.id[b]);
  }
  // Before the histories are carried: they follow by id into the sorted places.
  if (canonical) order_by_ids(fresh, p.next_id);
  lists_detail::carry_history(
      old, fresh, p.next_id, tracking, [](const B& x) -> const auto& { return x.id_i; },
      [&](std::uint32_t o) { return old.id_j[o]; }, [&](std::size_t k) { return fresh.id_j[k]; });
  return old.size();
}

// The same for the particle-wall candidates of model `model`: every movable
// particle within `skin` of a wall. Particle by particle (then wall by wall):
// the wall loop then walks the particles' data in memory order, and a
// particle's wall contacts lie together, so threads can own whole particles.
// A particle near a mesh wall is listed once per part (kernel/mesh_contacts.hpp);
// a history is carried by particle, wall and part. `id_order` (the canonical
// order; empty: memory order) lists the particles in increasing id instead, so
// that the reactions on the walls are summed in an order storage cannot change.
template <int D, typename M>
void list_walls(WallBucket<D, M>& bucket, int model, const Particles<D>& p,
                const std::vector<Wall<D>>& walls, const MeshSet<D>& meshes, const PairTable& pairs,
                double skin, bool tracking, const std::vector<std::uint32_t>& id_order) {
  using WB = WallBucket<D, M>;
  WB old = lists_detail::renew(bucket);
  WB& fresh = bucket;
  const std::size_t expect = old.size() + old.size() / 8;
  fresh.particle.reserve(expect), fresh.wall.reserve(expect), fresh.slot.reserve(expect);
  fresh.id.reserve(expect);
  const bool by_id = !id_order.empty();
  for (std::size_t k = 0; k < p.size(); ++k) {
    const std::size_t i = by_id ? id_order[k] : k;
    if (p.fixed[i]) continue;
    for (std::size_t w = 0; w < walls.size(); ++w) {
      const PairTable::Entry& e = pairs.at(p.material[i], walls[w].material);
      if (e.model != model) continue;
      int parts = 1;
      if (is_surface_wall(walls[w].type)) {
        // (A centre inside a solid polyline, whatever its distance from the chain, is
        // pushed out: resolve_mesh_contacts.)
        if (!meshes.near(w, p.position[i], p.radius[i] + skin) &&
            !meshes.inside_solid(w, p.position[i]))
          continue;
        parts = MeshSet<D>::Shape::max_hits;
      } else if (walls[w].clearance(p.position[i], p.radius[i]) >= skin) {
        continue;
      }
      for (int part = 0; part < parts; ++part) {
        fresh.particle.push_back(static_cast<std::uint32_t>(i));
        fresh.wall.push_back(static_cast<std::uint32_t>(w));
        fresh.slot.push_back(static_cast<std::uint32_t>(e.slot));
        fresh.id.push_back(p.id[i]);
        fresh.part.push_back(static_cast<std::uint8_t>(part));
      }
    }
  }
  fresh.part_normal.assign(fresh.size(), Vec<D>::Zero());
  constexpr std::int64_t K = MeshSet<D>::Shape::max_hits;
  lists_detail::carry_history(
      old, fresh, p.next_id, tracking, [](const WB& x) -> const auto& { return x.id; },
      [&](std::uint32_t o) { return static_cast<std::int64_t>(old.wall[o]) * K + old.part[o]; },
      [&](std::size_t k) { return static_cast<std::int64_t>(fresh.wall[k]) * K + fresh.part[k]; },
      [&](std::size_t k, std::uint32_t o) {
        if (o < old.part_normal.size()) fresh.part_normal[k] = old.part_normal[o];
      });
}

// A bucket's entries whose particles are all still stored, each entry's
// storage indices taken from its ids: the lists as they stand after particles
// were removed or moved since they were built (their indices then stale, their
// ids not), for writing them out. The histories and tracks go with their entries;
// offset is the caller's.
template <typename B, typename Particles>
B live_entries(const B& b, const Particles& p) {
  B out;
  const bool tracks = b.track.size() == b.size();
  for (std::size_t k = 0; k < b.size(); ++k) {
    if constexpr (B::is_pair) {
      const int a = p.index(b.id_i[k]), c = p.index(b.id_j[k]);
      if (a < 0 || c < 0) continue;
      out.i.push_back(static_cast<std::uint32_t>(a));
      out.j.push_back(static_cast<std::uint32_t>(c));
      out.id_i.push_back(b.id_i[k]);
      out.id_j.push_back(b.id_j[k]);
    } else {
      const int a = p.index(b.id[k]);
      if (a < 0) continue;
      out.particle.push_back(static_cast<std::uint32_t>(a));
      out.wall.push_back(b.wall[k]);
      out.id.push_back(b.id[k]);
      out.part.push_back(b.part[k]);
      using Normal = typename std::decay_t<decltype(b.part_normal)>::value_type;
      out.part_normal.push_back(k < b.part_normal.size() ? b.part_normal[k]
                                                         : Normal(Normal::Zero()));
    }
    out.slot.push_back(b.slot[k]);
    out.history.push_back(b.history[k]);
    if (tracks) out.track.push_back(b.track[k]);
  }
  return out;
}

// Moves the particle at storage index order[k] to k, every per-particle array
// and the id index with it. Whatever names particles by storage index (the
// lists) must be rebuilt afterwards.
template <int D>
void reorder_particles(Particles<D>& p, const std::vector<std::uint32_t>& order) {
  gather(p.position, order), gather(p.velocity, order), gather(p.force_torque, order);
  gather(p.spin, order), gather(p.radius, order), gather(p.inv_mass, order);
  gather(p.inv_inertia, order), gather(p.mass, order), gather(p.id, order);
  gather(p.material, order), gather(p.fixed, order);
  for (std::size_t k = 0; k < p.size(); ++k) p.index_of_id[p.id[k]] = static_cast<std::int32_t>(k);
}

// Reorders the particles' storage along a Morton (Z-order) curve of cells one
// median diameter wide: particles close in space end up close in memory, so
// the contact loop reads neighbours from cache. The lists must be rebuilt
// afterwards (histories follow by persistent id).
template <int D>
void sort_along_curve(Particles<D>& p) {
  const std::size_t n = p.size();
  if (n < 2) return;
  std::vector<double> radii(p.radius.begin(), p.radius.end());
  std::nth_element(radii.begin(), radii.begin() + n / 2, radii.end());
  const double cell = 2 * radii[n / 2];
  Vec<D> lo = p.position[0];
  for (const auto& x : p.position) lo = lo.cwiseMin(x);
  constexpr int bits = D == 2 ? 31 : 21;
  const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  std::vector<std::uint64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t k = 0;
    std::uint64_t c[D];
    for (int d = 0; d < D; ++d)
      c[d] = static_cast<std::uint64_t>(
          std::min(top, std::max(0.0, (p.position[i][d] - lo[d]) / cell)));
    for (int b = bits - 1; b >= 0; --b)
      for (int d = 0; d < D; ++d) k = k << 1 | ((c[d] >> b) & 1u);
    key[i] = k;
  }
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  std::stable_sort(perm.begin(), perm.end(), [&](auto a, auto b) { return key[a] < key[b]; });
  reorder_particles(p, perm);
}

}  // namespace granule
