// A batch of contacts, one array per quantity with a lane per contact, for the
// contact models that also write their law as one loop over the lanes
// (`force_batch`): with no branch in it, the compiler computes several lanes
// per vector instruction, where one contact at a time leaves the divider and
// the square root waiting on each other (docs/performance.md). What a lane
// holds is a ContactState and a ContactForce (contact_state.hpp), with their
// sign conventions; a lane that holds no contact is padded with a harmless
// one, so every batch is full and runs the same instructions.
//
// A model offers the batch in 3D by declaring, beside History, a
// `BatchHistory3` (its History<3> as arrays: load(lane, h), store(lane, h),
// pad(lane)) and
//   static void force_batch(const Params* const lanes[], BatchHistory3&, ContactBatch<3>&);
// (each lane's parameters: the contacts of a batch may belong to different
// material pairs); in 2D the same with `BatchHistory2` and ContactBatch<2>.
// The engine then uses it in that dimension for particle pairs (PairKernel,
// kernel/pair_kernel.hpp) and for particles against walls (WallKernel,
// kernel/wall_batch.hpp: there inv_mass_sum is 1/m of the particle); models
// without it take the per-contact force(). A model whose law reads inv_mass_sum only on some
// steps of a contact (the linear law: once, when it first touches) may say so
// with `static bool batch_needs_mass(const History<D>&)`: on the other steps the
// engine leaves the lane's inv_mass_sum at 1 and does not fetch the particles'
// masses (a cache line per particle the batch would not use).
//
// The law's parameters reach the lanes through the model's LaneParams<true>
// (one law for the batch) and LaneParams<false> (mixed laws), chosen by
// with_lane_params below.
//
// What it costs a model's author: the law written a second time, as loops
// over the lanes with every branch a select (a division or a root under a
// condition keeps the loop from vectorising), and a test that the two agree
// (tests/core/test_batch.cpp runs a scene both ways for every batched model);
// and a check with -fopt-info-vec that GCC did vectorise each loop, which no
// test sees (docs/architecture.md: a long loop may stay scalar whole).
#pragma once

#include <type_traits>
#include <utility>

#include "contact/contact_state.hpp"

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
  alignas(
      64) double effective_radius[lanes];  // R* = r_i r_j / (r_i + r_j), m (if the law reads it)
  // Out: the force on i (ContactForce).
  alignas(64) double normal_force[lanes];                 // N, positive repulsive
  alignas(64) double ftx[lanes], fty[lanes], ftz[lanes];  // tangential force on i, N
};

// The 2D batch: the tangent line is t = (-n_y, n_x), so the tangential slip
// velocity and force are their components along t (as the 2D laws read them).
template <>
struct ContactBatch<2> {
  static constexpr int lanes = batch_lanes;
  double dt = 0;                                  // s
  alignas(64) double nx[lanes], ny[lanes];        // unit normal, from j to i
  alignas(64) double overlap[lanes];              // m
  alignas(64) double normal_velocity[lanes];      // m/s, positive approaching
  alignas(64) double tangential_velocity[lanes];  // along t, m/s (Eq. 3.10)
  alignas(64) double inv_mass_sum[lanes];         // 1/kg
  alignas(64) double effective_radius[lanes];     // R*, m (if the law reads it)
  alignas(64) double normal_force[lanes];         // N, positive repulsive
  alignas(64) double tangential_force[lanes];     // along t, on i, N
};

// Calls run(q) with the lanes' laws as the model's LaneParams<true> (every
// lane under one law: its values in registers) or LaneParams<false> (each
// value an array over the lanes): the one dispatch of every force_batch.
template <typename M, typename Run>
inline void with_lane_params(const typename M::Params* const lane[], Run&& run) {
  bool one_law = true;
  for (int l = 1; l < batch_lanes; ++l) one_law &= lane[l] == lane[0];
  if (one_law)
    run(typename M::template LaneParams<true>(lane));
  else
    run(typename M::template LaneParams<false>(lane));
}

// Detected by calling it on the history (a law may write it as a template
// over the history type, whose address cannot be taken without arguments).
template <typename M, typename H, typename = void>
struct has_batch_needs_mass : std::false_type {};
template <typename M, typename H>
struct has_batch_needs_mass<M, H,
                            std::void_t<decltype(M::batch_needs_mass(std::declval<const H&>()))>>
    : std::true_type {};

// Does this contact's lane need inv_mass_sum this step?
template <typename M, typename H>
inline bool batch_needs_mass(const H& h) {
  if constexpr (has_batch_needs_mass<M, H>::value)
    return M::batch_needs_mass(h);
  else
    return true;
}

// Does model M offer force_batch in dimension D (a BatchHistory2 or BatchHistory3)?
template <typename M, int D, typename = void>
struct has_force_batch : std::false_type {};
template <typename M>
struct has_force_batch<M, 3, std::void_t<typename M::BatchHistory3>> : std::true_type {};
template <typename M>
struct has_force_batch<M, 2, std::void_t<typename M::BatchHistory2>> : std::true_type {};
template <typename M, int D>
struct batch_history;
template <typename M>
struct batch_history<M, 3> {
  using type = typename M::BatchHistory3;
};
template <typename M>
struct batch_history<M, 2> {
  using type = typename M::BatchHistory2;
};

// Steps 2-3 of Walton-Braun (Eqs. 3.7-3.8) for a tangential vector o kept in a
// batch's history: rotate_onto_plane() lane by lane into r. The series of
// rotate_onto_plane in every lane (no branch); a lane that turned further
// (x >= 1e-4, rare, or not finite) is redone with the exact rescale afterwards.
inline void rotate_lanes_onto_plane(const ContactBatch<3>& c, const double* __restrict ox,
                                    const double* __restrict oy, const double* __restrict oz,
                                    double* __restrict rx, double* __restrict ry,
                                    double* __restrict rz) {
  constexpr int L = batch_lanes;
  alignas(64) double turn[L];  // x of rotate_onto_plane: the series holds below 1e-4
  for (int l = 0; l < L; ++l) {
    const double old_sq = ox[l] * ox[l] + oy[l] * oy[l] + oz[l] * oz[l];
    const double along = c.nx[l] * ox[l] + c.ny[l] * oy[l] + c.nz[l] * oz[l];
    const double turned_sq = along * along / old_sq;
    const double x = old_sq > 0 ? turned_sq : 0.0;
    turn[l] = x;
    const double grow = 1.0 + x * (0.5 + x * (0.375 + x * 0.3125));
    rx[l] = (ox[l] - c.nx[l] * along) * grow;
    ry[l] = (oy[l] - c.ny[l] * along) * grow;
    rz[l] = (oz[l] - c.nz[l] * along) * grow;
  }
  for (int l = 0; l < L; ++l)
    if (!(turn[l] < 1e-4)) {
      const Vec<3> turned =
          rotate_onto_plane<3>(Vec<3>(ox[l], oy[l], oz[l]), Vec<3>(c.nx[l], c.ny[l], c.nz[l]));
      rx[l] = turned.x(), ry[l] = turned.y(), rz[l] = turned.z();
    }
}

}  // namespace granule
