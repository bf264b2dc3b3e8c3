// The engine's side of a batch of 3D particle-pair contacts (contact_batch.hpp):
// what the pair loop gathers per contact (in slot order), the geometry and
// the totals computed lane by lane (vector instructions), and the contacts'
// identities for adding the results back in slot order. Knows no contact law:
// the model's force_batch() runs between geometry() and totals().
#pragma once

#include <cmath>
#include <cstdint>

#include "contact/contact_batch.hpp"

namespace granule {

template <typename M>
struct PairBatch {
  static constexpr int lanes = batch_lanes;
  ContactBatch<3> c;
  typename M::BatchHistory history;
  int count = 0;  // lanes holding a contact; the rest are padding
  std::uint32_t k[lanes], i[lanes], j[lanes];
  const typename M::Params* params[lanes];  // each lane's law
  // Gathered: x_i - x_j, v_j - v_i, r_i w_i + r_j w_j, the radii.
  alignas(64) double dx[lanes], dy[lanes], dz[lanes];
  alignas(64) double vx[lanes], vy[lanes], vz[lanes];
  alignas(64) double wx[lanes], wy[lanes], wz[lanes];
  alignas(64) double r_i[lanes], r_j[lanes];
  // Results: the force on i (j feels minus it) and the torques about each centre.
  alignas(64) double fx[lanes], fy[lanes], fz[lanes];
  alignas(64) double tix[lanes], tiy[lanes], tiz[lanes];
  alignas(64) double tjx[lanes], tjy[lanes], tjz[lanes];

  // A harmless contact in the unused lanes (separated by half a metre, at
  // rest), so that every batch runs the same full-width loops.
  void pad() {
    for (int l = count; l < lanes; ++l) {
      dx[l] = 1, dy[l] = dz[l] = 0;
      vx[l] = vy[l] = vz[l] = 0;
      wx[l] = wy[l] = wz[l] = 0;
      r_i[l] = r_j[l] = 0.25;
      c.inv_mass_sum[l] = 1;
      params[l] = params[0];  // count > 0 when a batch is computed
      history.pad(l);
    }
  }

  // The contact geometry of the pair loop's per-contact path, lane by lane:
  // the normal from j to i, the overlap, the normal velocity and Eq. 3.10's
  // tangential slip velocity of j's surface relative to i's.
  void geometry() {
    for (int l = 0; l < lanes; ++l) {
      const double dist_sq = dx[l] * dx[l] + dy[l] * dy[l] + dz[l] * dz[l];
      const double dist = std::sqrt(dist_sq);
      const double inv_dist = dist * (1.0 / dist_sq);
      // Coincident centres: any direction will do, but a finite one.
      const bool apart = dist > 0;
      const double nx = apart ? dx[l] * inv_dist : 1.0;
      const double ny = apart ? dy[l] * inv_dist : 0.0;
      const double nz = apart ? dz[l] * inv_dist : 0.0;
      c.nx[l] = nx, c.ny[l] = ny, c.nz[l] = nz;
      c.overlap[l] = (r_i[l] + r_j[l]) - dist;
      const double vn = vx[l] * nx + vy[l] * ny + vz[l] * nz;
      c.normal_velocity[l] = vn;
      c.vtx[l] = (vx[l] - nx * vn) + (wy[l] * nz - wz[l] * ny);
      c.vty[l] = (vy[l] - ny * vn) + (wz[l] * nx - wx[l] * nz);
      c.vtz[l] = (vz[l] - nz * vn) + (wx[l] * ny - wy[l] * nx);
    }
  }

  // The total force on i and the torques about each centre, the contact
  // force applied at the contact point: levers -(r_i - a/2) n on i and
  // +(r_j - a/2) n on j, so the pair exerts no net torque.
  void totals() {
    for (int l = 0; l < lanes; ++l) {
      const double nx = c.nx[l], ny = c.ny[l], nz = c.nz[l];
      const double n_force = c.normal_force[l];
      const double ftx = c.ftx[l], fty = c.fty[l], ftz = c.ftz[l];
      fx[l] = n_force * nx + ftx;
      fy[l] = n_force * ny + fty;
      fz[l] = n_force * nz + ftz;
      const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
      const double lever_i = -(r_i[l] - 0.5 * c.overlap[l]);
      const double lever_j = -(r_j[l] - 0.5 * c.overlap[l]);
      tix[l] = lever_i * cx, tiy[l] = lever_i * cy, tiz[l] = lever_i * cz;
      tjx[l] = lever_j * cx, tjy[l] = lever_j * cy, tjz[l] = lever_j * cz;
    }
  }
};

}  // namespace granule
