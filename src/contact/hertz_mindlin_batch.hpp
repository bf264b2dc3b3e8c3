// Damped Hertz-Mindlin's force() (hertz_mindlin.hpp) for a batch of contacts
// (contact_batch.hpp): the same formulas in the same order, lane by lane,
// the tension clamp and the sliding cap as selects. In 2D the slip is kept
// as the vector History<2> holds, read along t = (-n_y, n_x).
#pragma once

#include <cmath>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "contact/hertz_mindlin.hpp"

namespace granule {

template <>
struct HertzMindlin::LaneParams<true> {
  double young_, shear_, damp_, mu_, ratio_;
  bool rescaled_;
  explicit LaneParams(const Params* const lane[]) {
    const Params& p = *lane[0];
    young_ = p.young_eff, shear_ = p.shear_eff, mu_ = p.friction;
    damp_ = 2 * std::sqrt(5.0 / 6.0) * p.damping;
    ratio_ = p.tangential_dashpot_ratio;
    rescaled_ = p.shrink_rescale;
  }
  bool any_rescaled() const { return rescaled_; }
  bool rescaled(int) const { return rescaled_; }
  double young(int) const { return young_; }
  double shear(int) const { return shear_; }
  double damp(int) const { return damp_; }
  double mu(int) const { return mu_; }
  double ratio(int) const { return ratio_; }
};

template <>
struct HertzMindlin::LaneParams<false> {
  static constexpr int L = batch_lanes;
  alignas(64) double young_[L], shear_[L], damp_[L], mu_[L], ratio_[L];
  bool rescaled_[L];
  bool any_ = false;
  explicit LaneParams(const Params* const lane[]) {
    for (int l = 0; l < L; ++l) {
      const Params& p = *lane[l];
      young_[l] = p.young_eff, shear_[l] = p.shear_eff, mu_[l] = p.friction;
      damp_[l] = 2 * std::sqrt(5.0 / 6.0) * p.damping;
      ratio_[l] = p.tangential_dashpot_ratio;
      rescaled_[l] = p.shrink_rescale;
      any_ = any_ || p.shrink_rescale;
    }
  }
  bool any_rescaled() const { return any_; }
  bool rescaled(int l) const { return rescaled_[l]; }
  double young(int l) const { return young_[l]; }
  double shear(int l) const { return shear_[l]; }
  double damp(int l) const { return damp_[l]; }
  double mu(int l) const { return mu_[l]; }
  double ratio(int l) const { return ratio_[l]; }
};

namespace hertz_mindlin_lanes {

// The normal force of lane l (the dashpot at the step's own time, as force()
// solves it) and the tangential stiffness S_t and damping c_t.
template <typename P, typename Batch>
inline double normal_force(const P& q, const Batch& c, int l, double per_slip_step, double& s_t,
                           double& c_t) {
  const double effective_mass = 1.0 / c.inv_mass_sum[l];
  const double root = std::sqrt(c.effective_radius[l] * c.overlap[l]);  // contact radius a
  const double s_n = 2 * q.young(l) * root;
  const double damp = q.damp(l);
  const double c_n = damp * std::sqrt(s_n * effective_mass);
  const double k = 0.5 * c_n * c.dt * c.inv_mass_sum[l];  // as force() (hertz_mindlin.hpp)
  const double normal = ((2.0 / 3.0) * s_n * c.overlap[l] + c_n * c.normal_velocity[l]) /
                        (1 + k + std::max(0.0, k - 1));
  s_t = 8 * q.shear(l) * root;
  c_t = HertzMindlin::tangential_damping(c_n * q.ratio(l), effective_mass, per_slip_step);
  return normal < 0 ? 0.0 : normal;
}

// shrink_rescale's factor per lane (HertzMindlin::shrink_factor; 1 where the lane's
// law does not rescale), in a loop of its own only where some lane's law does.
template <typename P, typename Batch>
inline void shrink_factors(const P& q, const Batch& c, double* factor) {
  for (int l = 0; l < batch_lanes; ++l) {
    const double f = HertzMindlin::shrink_factor(c.overlap[l], c.normal_velocity[l], c.dt);
    factor[l] = q.rescaled(l) ? f : 1.0;
  }
}

template <bool Rescaled, typename P>
inline void lanes_3d(const P& q, HertzMindlin::BatchHistory3& h, ContactBatch<3>& c) {
  constexpr int L = batch_lanes;
  const double dt = c.dt;
  alignas(64) double rx[L], ry[L], rz[L];  // the slip on the new tangent plane
  alignas(64) double stiffness_t[L], damping_t[L];
  // Two loops, as the linear law's: in one, GCC 12 vectorises neither (the
  // roots and divisions then run one lane at a time).
  const double per_slip_step = HertzMindlin::per_slip_step(dt);
  for (int l = 0; l < L; ++l)
    c.normal_force[l] = normal_force(q, c, l, per_slip_step, stiffness_t[l], damping_t[l]);
  rotate_lanes_onto_plane(c, h.sx, h.sy, h.sz, rx, ry, rz);
  if constexpr (Rescaled) {
    alignas(64) double factor[L];
    shrink_factors(q, c, factor);
    for (int l = 0; l < L; ++l) rx[l] *= factor[l], ry[l] *= factor[l], rz[l] *= factor[l];
  }
  for (int l = 0; l < L; ++l) {
    const double s_t = stiffness_t[l], c_t = damping_t[l];
    const double normal = c.normal_force[l];
    const double vx = c.vtx[l], vy = c.vty[l], vz = c.vtz[l];
    double sx = rx[l] + vx * dt, sy = ry[l] + vy * dt, sz = rz[l] + vz * dt;
    double tx = s_t * sx + c_t * vx, ty = s_t * sy + c_t * vy, tz = s_t * sz + c_t * vz;
    const double limit = q.mu(l) * normal;
    const double t_sq = tx * tx + ty * ty + tz * tz;
    const bool sliding = t_sq > limit * limit;  // then t_sq > 0
    const double scale = limit / std::sqrt(t_sq);
    tx = sliding ? tx * scale : tx, ty = sliding ? ty * scale : ty, tz = sliding ? tz * scale : tz;
    // The spring alone storing the capped force (force()).
    const bool stiff = s_t > 0;
    const double compliance = 1 / s_t;  // one division for the three components
    sx = sliding ? (stiff ? tx * compliance : 0.0) : sx;
    sy = sliding ? (stiff ? ty * compliance : 0.0) : sy;
    sz = sliding ? (stiff ? tz * compliance : 0.0) : sz;
    h.sx[l] = sx, h.sy[l] = sy, h.sz[l] = sz;
    c.ftx[l] = tx, c.fty[l] = ty, c.ftz[l] = tz;
  }
}

template <bool Rescaled, typename P>
inline void lanes_2d(const P& q, HertzMindlin::BatchHistory2& h, ContactBatch<2>& c) {
  const double dt = c.dt;
  const double per_slip_step = HertzMindlin::per_slip_step(dt);
  alignas(64) double factor[batch_lanes];
  if constexpr (Rescaled) shrink_factors(q, c, factor);
  for (int l = 0; l < batch_lanes; ++l) {
    double s_t, c_t;
    const double normal = normal_force(q, c, l, per_slip_step, s_t, c_t);
    c.normal_force[l] = normal;
    // rotate_onto_plane<2>: |old| along +t or -t, the side old projects to.
    const double nx = c.nx[l], ny = c.ny[l];
    const double old_sq = h.sx[l] * h.sx[l] + h.sy[l] * h.sy[l];
    const double along = h.sx[l] * -ny + h.sy[l] * nx;
    const double magnitude = std::sqrt(old_sq);
    const bool kept = old_sq > 0 && !(along * along <= 1e-30 * old_sq);
    double turned = kept ? (along > 0 ? magnitude : -magnitude) : 0.0;
    if constexpr (Rescaled) turned *= factor[l];
    const double v_t = c.tangential_velocity[l];
    double slip = turned + v_t * dt;
    double t = s_t * slip + c_t * v_t;
    const double limit = q.mu(l) * normal;
    const bool sliding = t * t > limit * limit;
    t = sliding ? (t > 0 ? limit : -limit) : t;
    slip = sliding ? (s_t > 0 ? t * (1 / s_t) : 0.0) : slip;
    h.sx[l] = slip * -ny, h.sy[l] = slip * nx;
    c.tangential_force[l] = t;
  }
}

template <typename History, typename Batch>
inline void dispatch(const HertzMindlin::Params* const lane[], History& h, Batch& c) {
  with_lane_params<HertzMindlin>(lane, [&](const auto& q) {
    const bool rescaled = q.any_rescaled();
    if constexpr (std::is_same_v<Batch, ContactBatch<2>>)
      rescaled ? lanes_2d<true>(q, h, c) : lanes_2d<false>(q, h, c);
    else
      rescaled ? lanes_3d<true>(q, h, c) : lanes_3d<false>(q, h, c);
  });
}

}  // namespace hertz_mindlin_lanes

inline void HertzMindlin::force_batch(const Params* const lane[], BatchHistory3& h,
                                      ContactBatch<3>& c) {
  hertz_mindlin_lanes::dispatch(lane, h, c);
}
inline void HertzMindlin::force_batch(const Params* const lane[], BatchHistory2& h,
                                      ContactBatch<2>& c) {
  hertz_mindlin_lanes::dispatch(lane, h, c);
}

}  // namespace granule
