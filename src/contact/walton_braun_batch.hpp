// Walton-Braun's force() (walton_braun.hpp) for a batch of contacts
// (contact_batch.hpp): the same formulas in the same order, lane by lane,
// every branch of section 3.3's steps written as a select, so that the lanes
// run as vector instructions. Eq. 3.3's exponent nu is 1 in every study of
// the dissertation; a batch with a lane of another exponent takes the
// instantiation that calls pow (one lane at a time, still without branches).
#pragma once

#include <cmath>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "contact/walton_braun.hpp"

namespace granule {

// One law for all lanes: its values in registers.
template <>
struct WaltonBraun::LaneParams<true> {
  double k_load_, k_unload_, set_fraction_, tau_, mu_, nu_;
  explicit LaneParams(const Params* const lane[]) {
    const Params& p = *lane[0];
    k_load_ = p.k_load, k_unload_ = p.k_unload, set_fraction_ = p.permanent_set_fraction;
    tau_ = p.tangential_ratio, mu_ = p.friction, nu_ = p.slip_exponent;
  }
  double k_load(int) const { return k_load_; }
  double k_unload(int) const { return k_unload_; }
  double set_fraction(int) const { return set_fraction_; }
  double tau(int) const { return tau_; }
  double mu(int) const { return mu_; }
  double nu(int) const { return nu_; }
};

// Lanes under different laws: each value as an array over the lanes.
template <>
struct WaltonBraun::LaneParams<false> {
  static constexpr int L = batch_lanes;
  alignas(64) double k_load_[L], k_unload_[L], set_fraction_[L], tau_[L], mu_[L], nu_[L];
  explicit LaneParams(const Params* const lane[]) {
    for (int l = 0; l < L; ++l) {
      const Params& p = *lane[l];
      k_load_[l] = p.k_load, k_unload_[l] = p.k_unload;
      set_fraction_[l] = p.permanent_set_fraction;
      tau_[l] = p.tangential_ratio, mu_[l] = p.friction, nu_[l] = p.slip_exponent;
    }
  }
  double k_load(int l) const { return k_load_[l]; }
  double k_unload(int l) const { return k_unload_[l]; }
  double set_fraction(int l) const { return set_fraction_[l]; }
  double tau(int l) const { return tau_[l]; }
  double mu(int l) const { return mu_[l]; }
  double nu(int l) const { return nu_[l]; }
};

namespace walton_braun_lanes {

// Eqs. 3.1-3.2 with partial latching for lane l: the normal force, a_max
// updated, and the initial tangential stiffness k0 of Eq. 3.4 (step 4).
template <typename P>
inline double normal_force(const P& q, int l, double overlap, double& max_overlap, double& k0) {
  const bool loading = overlap >= max_overlap;
  max_overlap = loading ? overlap : max_overlap;
  const double permanent_set = max_overlap * q.set_fraction(l);
  const double raw = loading ? q.k_load(l) * overlap : q.k_unload(l) * (overlap - permanent_set);
  k0 =
      q.tau(l) * (WaltonBraun::on_loading_line(overlap, max_overlap) ? q.k_load(l) : q.k_unload(l));
  return raw < 0 ? 0.0 : raw;
}

// Eq. 3.3 read along u: the fraction of k0 left, (1 - (T - T*) / (mu N - T*))^nu.
template <bool UnitExponent, typename P>
inline double stiffness_fraction(const P& q, int l, double t_u, double star_u, double limit) {
  const double room = limit - star_u;
  double fraction = room > 0 ? 1.0 - (t_u - star_u) / room : 0.0;
  fraction = fraction < 0 ? 0.0 : (fraction > 1 ? 1.0 : fraction);
  if constexpr (UnitExponent)
    return fraction;
  else
    return q.nu(l) == 1.0 ? fraction : std::pow(fraction, q.nu(l));
}

template <bool UnitExponent, typename P>
inline void lanes_2d(const P& q, WaltonBraun::BatchHistory2& h, ContactBatch<2>& c) {
  const double dt = c.dt;
  for (int l = 0; l < batch_lanes; ++l) {
    double k0;
    const double normal = normal_force(q, l, c.overlap[l], h.max_overlap[l], k0);
    c.normal_force[l] = normal;
    const double limit = q.mu(l) * normal;
    // force_2d(): every vector is its component along t.
    const double t_force = h.tangential[l], previous_u = h.load_direction[l];
    const double slip = c.tangential_velocity[l] * dt;  // Eq. 3.10
    // Step 4 (Eq. 3.9): the sign of T, or of the slip for T = 0.
    const double t_hat = t_force > 0   ? 1.0
                         : t_force < 0 ? -1.0
                         : slip > 0    ? 1.0
                         : slip < 0    ? -1.0
                                       : 0.0;
    const double slip_parallel = slip * t_hat;  // Eq. 3.11
    // Step 8 (Eq. 3.13).
    const double previous_normal = h.previous_normal[l];
    double reversal = previous_normal > 0 ? h.reversal[l] * (normal / previous_normal) : 0.0;
    const bool moving = slip_parallel != 0;
    const double u = slip > 0 ? 1.0 : -1.0;
    reversal = moving && u * previous_u < 0 ? t_force : reversal;
    reversal = moving && WaltonBraun::forgets_reversal(reversal * u, limit) ? 0.0 : reversal;
    const double fraction =
        stiffness_fraction<UnitExponent>(q, l, t_force * u, reversal * u, limit);
    const double k_t = moving ? k0 * fraction : k0;
    // Steps 10-13 (Eqs. 3.14-3.17).
    double t_new = t_force + k_t * slip;
    t_new = t_new > limit ? limit : t_new;
    t_new = t_new < -limit ? -limit : t_new;
    // No friction, or N = 0 in the permanent-set gap: |T| <= mu N = 0.
    const bool free = !(limit > 0);
    h.tangential[l] = free ? 0.0 : t_new;
    h.reversal[l] = free ? 0.0 : reversal;
    h.load_direction[l] = free || !moving ? previous_u : u;
    h.previous_normal[l] = normal;
    c.tangential_force[l] = free ? 0.0 : t_new;
  }
}

template <bool UnitExponent, typename P>
inline void lanes_3d(const P& q, WaltonBraun::BatchHistory3& h, ContactBatch<3>& c) {
  constexpr int L = batch_lanes;
  const double dt = c.dt;
  // Steps 2-3 (Eqs. 3.7-3.8): T, T* and u onto the current tangent plane.
  alignas(64) double tx[L], ty[L], tz[L], rx[L], ry[L], rz[L], ux[L], uy[L], uz[L];
  rotate_lanes_onto_plane(c, h.tx, h.ty, h.tz, tx, ty, tz);
  rotate_lanes_onto_plane(c, h.rx, h.ry, h.rz, rx, ry, rz);
  rotate_lanes_onto_plane(c, h.ux, h.uy, h.uz, ux, uy, uz);
  // The normal force and k0 in a loop of their own: in one loop with the
  // rest, GCC 12 vectorises none of it (the roots and divisions then run one
  // lane at a time).
  alignas(64) double stiffness_0[L];
  for (int l = 0; l < L; ++l)
    c.normal_force[l] = normal_force(q, l, c.overlap[l], h.max_overlap[l], stiffness_0[l]);
  for (int l = 0; l < L; ++l) {
    const double k0 = stiffness_0[l];
    const double normal = c.normal_force[l];
    const double limit = q.mu(l) * normal;
    // Step 5 (Eq. 3.10).
    const double sx = c.vtx[l] * dt, sy = c.vty[l] * dt, sz = c.vtz[l] * dt;
    // Step 4 (Eq. 3.9): the unit vector of T; for T = 0 that of the slip.
    const double t_mag = std::sqrt(tx[l] * tx[l] + ty[l] * ty[l] + tz[l] * tz[l]);
    const double s_mag = std::sqrt(sx * sx + sy * sy + sz * sz);
    const bool has_t = t_mag > 0, has_hat = has_t || s_mag > 0;
    const double mag = has_t ? t_mag : s_mag;
    const double hx = has_hat ? (has_t ? tx[l] : sx) / mag : 0.0;
    const double hy = has_hat ? (has_t ? ty[l] : sy) / mag : 0.0;
    const double hz = has_hat ? (has_t ? tz[l] : sz) / mag : 0.0;
    // Steps 6-7 (Eqs. 3.11-3.12).
    const double slip_parallel = sx * hx + sy * hy + sz * hz;
    const double px = slip_parallel * hx, py = slip_parallel * hy, pz = slip_parallel * hz;
    const double qx = sx - px, qy = sy - py, qz = sz - pz;
    // Step 8 (Eq. 3.13).
    const double previous_normal = h.previous_normal[l];
    const double scale = normal / previous_normal;
    const bool fresh = !(previous_normal > 0);
    double r_x = fresh ? 0.0 : rx[l] * scale, r_y = fresh ? 0.0 : ry[l] * scale,
           r_z = fresh ? 0.0 : rz[l] * scale;
    const bool moving = slip_parallel != 0;
    const double sign = slip_parallel > 0 ? 1.0 : -1.0;
    const double vx = sign * hx, vy = sign * hy, vz = sign * hz;  // u of this increment
    // A loading reversal: T* takes the value T had when the direction flipped.
    const bool flipped = moving && vx * ux[l] + vy * uy[l] + vz * uz[l] < 0;
    r_x = flipped ? tx[l] : r_x, r_y = flipped ? ty[l] : r_y, r_z = flipped ? tz[l] : r_z;
    // Step 9 (Eq. 3.3) read along u.
    const double t_u = tx[l] * vx + ty[l] * vy + tz[l] * vz;
    const double star_reached = r_x * vx + r_y * vy + r_z * vz;
    const bool forgotten = moving && WaltonBraun::forgets_reversal(star_reached, limit);
    r_x = forgotten ? 0.0 : r_x, r_y = forgotten ? 0.0 : r_y, r_z = forgotten ? 0.0 : r_z;
    const double star_u = forgotten ? 0.0 : star_reached;
    const double fraction = stiffness_fraction<UnitExponent>(q, l, t_u, star_u, limit);
    const double k_t = moving ? k0 * fraction : k0;
    // Steps 10-12 (Eqs. 3.14-3.16), then step 13 (Eq. 3.17): |T| <= mu N.
    double nx = tx[l] + k_t * px + k0 * qx, ny = ty[l] + k_t * py + k0 * qy,
           nz = tz[l] + k_t * pz + k0 * qz;
    const double new_sq = nx * nx + ny * ny + nz * nz;
    const bool capped = new_sq > limit * limit;
    const double cap = limit / std::sqrt(new_sq);
    nx = capped ? nx * cap : nx, ny = capped ? ny * cap : ny, nz = capped ? nz * cap : nz;
    // No friction, or N = 0 in the permanent-set gap: T and T* cleared, u kept as it was.
    const bool free = !(limit > 0);
    h.tx[l] = free ? 0.0 : nx, h.ty[l] = free ? 0.0 : ny, h.tz[l] = free ? 0.0 : nz;
    h.rx[l] = free ? 0.0 : r_x, h.ry[l] = free ? 0.0 : r_y, h.rz[l] = free ? 0.0 : r_z;
    const bool keep_u = free, new_u = !free && moving;
    h.ux[l] = keep_u ? h.ux[l] : new_u ? vx : ux[l];
    h.uy[l] = keep_u ? h.uy[l] : new_u ? vy : uy[l];
    h.uz[l] = keep_u ? h.uz[l] : new_u ? vz : uz[l];
    h.previous_normal[l] = normal;
    c.ftx[l] = free ? 0.0 : nx, c.fty[l] = free ? 0.0 : ny, c.ftz[l] = free ? 0.0 : nz;
  }
}

// The lanes' laws: one law or many, exponent 1 or not.
template <typename History, typename Batch>
inline void dispatch(const WaltonBraun::Params* const lane[], History& h, Batch& c) {
  bool unit_exponent = true;
  for (int l = 0; l < batch_lanes; ++l) unit_exponent &= lane[l]->slip_exponent == 1.0;
  with_lane_params<WaltonBraun>(lane, [&](const auto& q) {
    if constexpr (std::is_same_v<Batch, ContactBatch<2>>) {
      if (unit_exponent)
        lanes_2d<true>(q, h, c);
      else
        lanes_2d<false>(q, h, c);
    } else {
      if (unit_exponent)
        lanes_3d<true>(q, h, c);
      else
        lanes_3d<false>(q, h, c);
    }
  });
}

}  // namespace walton_braun_lanes

inline void WaltonBraun::force_batch(const Params* const lane[], BatchHistory2& h,
                                     ContactBatch<2>& c) {
  walton_braun_lanes::dispatch(lane, h, c);
}
inline void WaltonBraun::force_batch(const Params* const lane[], BatchHistory3& h,
                                     ContactBatch<3>& c) {
  walton_braun_lanes::dispatch(lane, h, c);
}

}  // namespace granule
