// The engine's side of a batch of 2D particle-pair contacts (contact_batch.hpp),
// as pair_batch.hpp is for 3D: what the pair loop gathers per contact (in slot
// order), the geometry and the totals lane by lane, and the contacts'
// identities for adding the results back in slot order. The formulas are the
// per-contact path's (pair_kernel.hpp), in the same order, so the two agree
// to round-off. Knows no contact law: the model's force_batch() runs between
// geometry() and totals().
#pragma once

#include <cmath>
#include <cstdint>

#include "contact/contact_batch.hpp"
#include "core/particles.hpp"

namespace granule {

template <int D, typename M>
struct PairBatch;

template <typename M>
struct PairBatch<2, M> {
  static constexpr int lanes = batch_lanes;
  ContactBatch<2> c;
  typename M::BatchHistory2 history;
  int count = 0;  // lanes holding a contact; the rest are padding
  std::uint32_t k[lanes], i[lanes], j[lanes];
  const typename M::Params* params[lanes];  // each lane's law
  // Gathered: x_i - x_j, v_j - v_i, the spins, the radii.
  alignas(64) double dx[lanes], dy[lanes];
  alignas(64) double vx[lanes], vy[lanes];
  alignas(64) double wi[lanes], wj[lanes];
  alignas(64) double r_i[lanes], r_j[lanes];
  // Results: the force on i (j feels minus it) and the torques about each centre.
  alignas(64) double fx[lanes], fy[lanes];
  alignas(64) double ti[lanes], tj[lanes];

  using History2 = typename M::template History<2>;

  void gather_lane(int l, const Vec<2>& x_i, const Vec<2>& x_j, const Vec<2>& v_i,
                   const Vec<2>& v_j, double w_i, double w_j, double radius_i, double radius_j,
                   double inv_mass_sum, const History2& h) {
    dx[l] = x_i[0] - x_j[0], dy[l] = x_i[1] - x_j[1];
    vx[l] = v_j[0] - v_i[0], vy[l] = v_j[1] - v_i[1];
    wi[l] = w_i, wj[l] = w_j;
    r_i[l] = radius_i, r_j[l] = radius_j;
    c.inv_mass_sum[l] = inv_mass_sum;
    history.load(l, h);
  }
  // Component `axis` of lane l's x_i - x_j, for the periodic wrap.
  double& separation(int l, int axis) { return axis == 0 ? dx[l] : dy[l]; }

  // The 3D batch's steps around the law (pair_batch.hpp); in 2D the lanes are
  // stored directly, so moving them in and out costs nothing.
  void lanes_in() {}
  void lanes_out() {}
  void store_history(int l, History2& h) const { history.store(l, h); }

  void add_i(ForceTorque<2>& p, int l) const {
    p.force += force_on_i(l);
    p.torque += ti[l];
  }
  void add_j(ForceTorque<2>& p, int l) const {
    p.force += Vec<2>(-force_on_i(l));
    p.torque += tj[l];
  }
  Vec<2> force_on_i(int l) const { return Vec<2>(fx[l], fy[l]); }
  double torque_on_i(int l) const { return ti[l]; }
  double torque_on_j(int l) const { return tj[l]; }
  // For the contact log.
  Vec<2> normal(int l) const { return Vec<2>(c.nx[l], c.ny[l]); }
  Vec<2> tangential_force(int l) const {
    return Vec<2>(-c.tangential_force[l] * c.ny[l], c.tangential_force[l] * c.nx[l]);
  }

  // A harmless contact in the unused lanes (separated by half a metre, at rest).
  void pad() {
    for (int l = count; l < lanes; ++l) {
      dx[l] = 1, dy[l] = 0;
      vx[l] = vy[l] = 0;
      wi[l] = wj[l] = 0;
      r_i[l] = r_j[l] = 0.25;
      c.inv_mass_sum[l] = 1;
      params[l] = params[0];  // count > 0 when a batch is computed
      history.pad(l);
    }
  }

  // The per-contact path's geometry lane by lane: the normal from j to i,
  // the overlap, the normal velocity, and Eq. 3.10's tangential slip velocity
  // of j's surface relative to i's at the contact point (levers r - a/2) as a
  // vector, then along t = (-n_y, n_x).
  void geometry() {
    for (int l = 0; l < lanes; ++l) {
      const double dist_sq = dx[l] * dx[l] + dy[l] * dy[l];
      const double dist = std::sqrt(dist_sq);
      const double inv_dist = dist * (1.0 / dist_sq);
      const bool apart = dist > 0;
      const double nx = apart ? dx[l] * inv_dist : 1.0;
      const double ny = apart ? dy[l] * inv_dist : 0.0;
      c.nx[l] = nx, c.ny[l] = ny;
      c.overlap[l] = (r_i[l] + r_j[l]) - dist;
      if constexpr (uses_effective_radius<M>::value)
        c.effective_radius[l] = r_i[l] * r_j[l] / (r_i[l] + r_j[l]);
      const double vn = vx[l] * nx + vy[l] * ny;
      c.normal_velocity[l] = vn;
      // w x n for a spin about z: (-w n_y, w n_x).
      const double overlap = c.overlap[l];
      const double w = (r_i[l] - 0.5 * overlap) * wi[l] + (r_j[l] - 0.5 * overlap) * wj[l];
      const double tvx = (vx[l] - nx * vn) + -w * ny;
      const double tvy = (vy[l] - ny * vn) + w * nx;
      c.tangential_velocity[l] = tvx * -ny + tvy * nx;
    }
  }

  // The total force on i and the torques about each centre, the force applied
  // at the contact point (levers -(r_i - a/2) n on i and +(r_j - a/2) n on j).
  void totals() {
    for (int l = 0; l < lanes; ++l) {
      const double nx = c.nx[l], ny = c.ny[l];
      const double n_force = c.normal_force[l], t_force = c.tangential_force[l];
      const double ftx = t_force * -ny, fty = t_force * nx;
      fx[l] = n_force * nx + ftx;
      fy[l] = n_force * ny + fty;
      const double cz = nx * fty - ny * ftx;
      ti[l] = -(r_i[l] - 0.5 * c.overlap[l]) * cz;
      tj[l] = -(r_j[l] - 0.5 * c.overlap[l]) * cz;
    }
  }
};

}  // namespace granule
