// Particle storage: one array per quantity (structure of arrays), hot data
// (position, velocity, force...) apart from cold (id, material). A particle's
// persistent id never changes; its storage index may (re-sorting, removal),
// so Lua handles and contact histories hold ids, never indices.
#pragma once

#include <cstdint>
#include <vector>

#include "core/hot_array.hpp"
#include "core/types.hpp"

namespace granule {

// The force and torque on a particle, side by side in one cache line: the
// contact loop adds to both for every contact, and in large scenes the
// partner's force and torque, in two arrays, were two misses per contact
// (docs/performance.md, "Force and torque on one cache line").
template <int D>
struct alignas(D == 3 ? 64 : 32) ForceTorque {
  Vec<D> force = Vec<D>::Zero();         // N
  Spin<D> torque = Dim<D>::zero_spin();  // N m
};

// In 3D force and torque each fill half of the line, the fourth double of
// each left at zero, so that the batched pair loop adds either as one vector
// of four doubles (pair_batch.hpp).
template <>
struct alignas(64) ForceTorque<3> {
  Vec<3> force = Vec<3>::Zero();  // N
  double force_pad = 0;
  Spin<3> torque = Dim<3>::zero_spin();  // N m
  double torque_pad = 0;
};

template <int D>
struct Particles {
  using V = Vec<D>;
  using S = Spin<D>;
  // hot
  HotArray<V> position, velocity;
  HotArray<S> spin;
  HotArray<ForceTorque<D>> force_torque;  // summed anew every step
  HotArray<double> radius, inv_mass, inv_inertia;
  HotArray<double> mass;  // kg, also for fixed particles (read by the integration for gravity)
  // cold
  std::vector<std::int64_t> id;
  std::vector<std::int32_t> material;
  // fixed_flag: infinite mass, moved only at a velocity the scene set (leapfrog.hpp);
  // a spread run's ghosts carry another bit too (Simulation::ghost_flag).
  static constexpr std::uint8_t fixed_flag = 1;
  std::vector<std::uint8_t> fixed;
  std::vector<std::int32_t> index_of_id;  // -1 for removed ids
  std::int64_t next_id = 0;

  std::size_t size() const { return position.size(); }

  int add(const V& x, const V& v, const S& w, double r, double density, int mat, bool is_fixed) {
    const double m = sphere_mass(r, density);
    const double inertia = sphere_inertia(m, r);
    position.push_back(x);
    velocity.push_back(v);  // a fixed particle's: its prescribed motion (leapfrog.hpp)
    force_torque.push_back({});
    spin.push_back(w);
    radius.push_back(r);
    mass.push_back(m);
    inv_mass.push_back(is_fixed ? 0.0 : 1.0 / m);
    inv_inertia.push_back(is_fixed ? 0.0 : 1.0 / inertia);
    id.push_back(next_id);
    material.push_back(mat);
    fixed.push_back(is_fixed ? fixed_flag : 0);
    index_of_id.push_back(static_cast<std::int32_t>(size() - 1));
    return static_cast<int>(next_id++);
  }

  // Index of a live particle, or -1.
  int index(std::int64_t pid) const {
    if (pid < 0 || pid >= static_cast<std::int64_t>(index_of_id.size())) return -1;
    return index_of_id[pid];
  }

  // The live particles' storage indices in increasing id: an order no re-sort
  // of the storage changes (the canonical order, SimulationBase::set_canonical_order).
  std::vector<std::uint32_t> in_id_order() const {
    std::vector<std::uint32_t> order;
    order.reserve(size());
    for (const std::int32_t k : index_of_id)
      if (k >= 0) order.push_back(static_cast<std::uint32_t>(k));
    return order;
  }
};

}  // namespace granule
