// A batch of contacts, one array per quantity with a lane per contact, for the
// contact models that also write their law as one loop over the lanes
// (`force_batch`): with no branch in it, the compiler computes several lanes
// per vector instruction, where one contact at a time leaves the divider and
// the square root waiting on each other (docs/performance.md). What a lane
// holds is a ContactState and a ContactForce (contact_state.hpp), with their
// sign conventions; a lane that holds no contact is padded with a harmless
// one, so every batch is full and runs the same instructions.
//
// A model offers the batch by declaring, beside History, a `BatchHistory`
// (its history as arrays: load(lane, h), store(lane, h), pad(lane)) and
//   static void force_batch(const Params* const lanes[], BatchHistory&, ContactBatch<3>&);
// (each lane's parameters: the contacts of a batch may belong to different
// material pairs). The engine then uses it for particle pairs in 3D
// (PairKernel, kernel/pair_kernel.hpp); 2D scenes, wall contacts and models without it take the
// per-contact force(). A model whose law reads inv_mass_sum only on some
// steps of a contact (the linear law: once, when it first touches) may say so
// with `static bool batch_needs_mass(const History3&)`: on the other steps the
// engine leaves the lane's inv_mass_sum at 1 and does not fetch the particles'
// masses (a cache line per particle the batch would not use).
#pragma once

#include <type_traits>

namespace granule {

constexpr int batch_lanes = 32;

template <int D>
struct ContactBatch;

template <>
struct ContactBatch<3> {
  static constexpr int lanes = batch_lanes;
  double dt = 0;  // s
  // In: the geometry and kinematics of each lane (ContactState).
  alignas(64) double nx[lanes], ny[lanes], nz[lanes];     // unit normal, from j to i
  alignas(64) double overlap[lanes];                      // m
  alignas(64) double normal_velocity[lanes];              // m/s, positive approaching
  alignas(64) double vtx[lanes], vty[lanes], vtz[lanes];  // tangential velocity, m/s
  alignas(64) double inv_mass_sum[lanes];                 // 1/kg
  // Out: the force on i (ContactForce).
  alignas(64) double normal_force[lanes];                 // N, positive repulsive
  alignas(64) double ftx[lanes], fty[lanes], ftz[lanes];  // tangential force on i, N
};

template <typename M, typename = void>
struct has_batch_needs_mass : std::false_type {};
template <typename M>
struct has_batch_needs_mass<M, std::void_t<decltype(&M::batch_needs_mass)>> : std::true_type {};

// Does this contact's lane need inv_mass_sum this step?
template <typename M, typename H>
inline bool batch_needs_mass(const H& h) {
  if constexpr (has_batch_needs_mass<M>::value)
    return M::batch_needs_mass(h);
  else
    return true;
}

template <typename M, typename = void>
struct has_force_batch : std::false_type {};
template <typename M>
struct has_force_batch<M, std::void_t<typename M::BatchHistory>> : std::true_type {};

}  // namespace granule
