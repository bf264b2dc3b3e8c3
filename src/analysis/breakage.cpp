#include "analysis/breakage.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace granule::analysis {

std::vector<Bond> normalized_bonds(std::vector<Bond> bonds) {
  for (Bond& b : bonds) {
    if (b.a < 0 || b.b < 0)
      throw std::invalid_argument(fmt::format("bond ({}, {}): ids must be >= 0", b.a, b.b));
    if (b.a == b.b)
      throw std::invalid_argument(
          fmt::format("bond ({}, {}): a particle bonded to itself", b.a, b.b));
    if (b.a > b.b) std::swap(b.a, b.b);
  }
  std::sort(bonds.begin(), bonds.end());
  bonds.erase(std::unique(bonds.begin(), bonds.end()), bonds.end());
  return bonds;
}

std::vector<Bond> surviving_bonds(const std::vector<Bond>& initial, const std::vector<Bond>& now) {
  std::vector<Bond> out;
  std::set_intersection(initial.begin(), initial.end(), now.begin(), now.end(),
                        std::back_inserter(out));
  return out;
}

DisjointSets::DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
  std::iota(parent_.begin(), parent_.end(), std::size_t{0});
}

std::size_t DisjointSets::find(std::size_t i) {
  while (parent_[i] != i) {
    parent_[i] = parent_[parent_[i]];  // path halving
    i = parent_[i];
  }
  return i;
}

void DisjointSets::unite(std::size_t i, std::size_t j) {
  i = find(i);
  j = find(j);
  if (i == j) return;
  if (size_[i] < size_[j]) std::swap(i, j);
  parent_[j] = i;
  size_[i] += size_[j];
}

Fragments find_fragments(const std::vector<std::int64_t>& ids, const std::vector<double>& masses,
                         const std::vector<Bond>& bonds) {
  if (ids.size() != masses.size())
    throw std::invalid_argument(
        fmt::format("find_fragments: {} ids but {} masses", ids.size(), masses.size()));
  std::unordered_map<std::int64_t, std::size_t> index_of;
  index_of.reserve(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (!(masses[k] > 0) || !std::isfinite(masses[k]))
      throw std::invalid_argument(fmt::format(
          "find_fragments: particle {} has mass {} (must be > 0 [kg])", ids[k], masses[k]));
    if (!index_of.emplace(ids[k], k).second)
      throw std::invalid_argument(fmt::format("find_fragments: particle {} listed twice", ids[k]));
  }
  DisjointSets sets(ids.size());
  for (const Bond& b : bonds) {
    auto ia = index_of.find(b.a), ib = index_of.find(b.b);
    if (ia == index_of.end() || ib == index_of.end()) continue;
    sets.unite(ia->second, ib->second);
  }
  // One entry per root: its mass, size and lowest member id (for a stable order).
  struct Cluster {
    double mass = 0;
    std::int64_t members = 0;
    std::int64_t lowest_id = 0;
  };
  std::unordered_map<std::size_t, std::size_t> cluster_of_root;
  std::vector<Cluster> clusters;
  std::vector<std::size_t> cluster_of(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const std::size_t root = sets.find(k);
    auto [it, fresh] = cluster_of_root.emplace(root, clusters.size());
    if (fresh) clusters.push_back({0, 0, ids[k]});
    Cluster& c = clusters[it->second];
    c.mass += masses[k];
    c.members += 1;
    c.lowest_id = std::min(c.lowest_id, ids[k]);
    cluster_of[k] = it->second;
  }
  std::vector<std::size_t> order(clusters.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    if (clusters[x].mass != clusters[y].mass) return clusters[x].mass > clusters[y].mass;
    return clusters[x].lowest_id < clusters[y].lowest_id;
  });
  std::vector<int> rank(clusters.size());
  Fragments out;
  for (std::size_t r = 0; r < order.size(); ++r) {
    rank[order[r]] = static_cast<int>(r);
    out.mass.push_back(clusters[order[r]].mass);
    out.members.push_back(clusters[order[r]].members);
  }
  out.ids = ids;
  out.label.resize(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) out.label[k] = rank[cluster_of[k]];
  return out;
}

BreakageSummary summarize_breakage(const std::vector<Bond>& initial_bonds,
                                   const std::vector<Bond>& bonds, const Fragments& fragments,
                                   double initial_mass, const FragmentClasses& classes,
                                   std::int64_t initial_count) {
  if (!(initial_mass > 0) || !std::isfinite(initial_mass))
    throw std::invalid_argument(
        fmt::format("breakage: initial_mass must be > 0 [kg], got {}", initial_mass));
  if (!(classes.fines > 0 && classes.fines <= classes.debris && classes.debris <= classes.large &&
        classes.large < 1))
    throw std::invalid_argument(fmt::format(
        "breakage: fragment classes need 0 < fines <= debris <= large < 1 (mass fractions), got "
        "fines = {}, debris = {}, large = {}",
        classes.fines, classes.debris, classes.large));
  BreakageSummary s;
  s.initial_bonds = static_cast<std::int64_t>(initial_bonds.size());
  s.bonds = static_cast<std::int64_t>(bonds.size());
  // Both lists are sorted: one merge pass counts the bonds kept.
  std::int64_t kept = 0;
  auto i = initial_bonds.begin();
  auto j = bonds.begin();
  while (i != initial_bonds.end() && j != bonds.end()) {
    if (*i < *j) {
      ++i;
    } else if (*j < *i) {
      ++j;
    } else {
      ++kept, ++i, ++j;
    }
  }
  s.broken_bonds = s.initial_bonds - kept;
  s.new_bonds = s.bonds - kept;
  s.damage_ratio =
      s.initial_bonds > 0 ? static_cast<double>(s.broken_bonds) / s.initial_bonds : 0.0;
  s.initial_mass = initial_mass;
  s.fragments = static_cast<std::int64_t>(fragments.count());
  if (initial_count < 0)
    throw std::invalid_argument(
        fmt::format("breakage: initial_count must be >= 0 primaries, got {}", initial_count));
  s.initial_count =
      initial_count > 0 ? initial_count : static_cast<std::int64_t>(fragments.ids.size());
  double fines_mass = 0;
  for (std::size_t f = 0; f < fragments.count(); ++f) {
    const double fraction = fragments.mass[f] / initial_mass;
    if (fraction > classes.large) {
      ++s.large;
    } else if (fraction >= classes.debris) {
      ++s.medium;
    } else {
      ++s.small;
      s.debris_mass += fragments.mass[f];
      if (fraction < classes.fines) {
        ++s.fines;
        fines_mass += fragments.mass[f];
      }
    }
    if (fragments.members[f] == 1) ++s.singles;
    // By size: n < debris N.
    const std::int64_t n = fragments.members[f];
    if (static_cast<double>(n) < classes.debris * static_cast<double>(s.initial_count)) {
      ++s.debris_by_size;
      s.debris_ratio_by_size += fragments.mass[f] / initial_mass;
      if (n == 1) {
        s.singles_ratio += fragments.mass[f] / initial_mass;
      } else {
        ++s.bonded_debris;
        s.bonded_debris_ratio += fragments.mass[f] / initial_mass;
      }
    }
  }
  s.debris_ratio = s.debris_mass / initial_mass;
  s.fines_ratio = fines_mass / initial_mass;
  s.largest_fraction = fragments.count() ? fragments.mass[0] / initial_mass : 0.0;
  return s;
}

ParallelBondState parallel_bond_state(const std::vector<std::int64_t>& ids,
                                      const std::vector<ParallelBondRecord>& records) {
  const std::unordered_set<std::int64_t> listed(ids.begin(), ids.end());
  ParallelBondState s;
  std::vector<Bond> intact;
  for (const ParallelBondRecord& r : records) {
    if (r.a < 0 || r.b < 0 || r.a == r.b)
      throw std::invalid_argument(
          fmt::format("parallel bond ({}, {}): ids must be >= 0 and differ", r.a, r.b));
    if (!listed.count(r.a) || !listed.count(r.b)) continue;
    ++s.made;
    if (r.broken)
      ++s.broken;
    else
      intact.push_back({r.a, r.b});
  }
  s.damage_ratio = s.made > 0 ? static_cast<double>(s.broken) / s.made : 0.0;
  s.intact = normalized_bonds(std::move(intact));
  return s;
}

}  // namespace granule::analysis
