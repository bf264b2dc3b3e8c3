// The engine's side of a batch of particle-wall contacts (contact_batch.hpp),
// as pair_batch.hpp and pair_batch_2d.hpp are for particle pairs: what the
// wall loop gathers per contact (in slot order), the kinematics and the
// totals lane by lane, and the contacts' identities for adding the results
// back in slot order. The wall's own geometry (Wall::contact, or a mesh's
// WallTouch) is found per candidate before a contact joins a batch; the
// formulas after it are the per-contact path's (wall_kernel.hpp), in the same
// order, so the two agree to round-off. Knows no contact law: the model's
// force_batch() runs between kinematics() and totals().
#pragma once

#include <cstdint>

#include "contact/contact_batch.hpp"
#include "core/particles.hpp"

namespace granule {

template <int D, typename M>
struct WallBatch {
  static constexpr int lanes = batch_lanes;
  using V = Vec<D>;
  using S = Spin<D>;
  using History = typename M::template History<D>;
  ContactBatch<D> c;
  typename batch_history<M, D>::type history;
  int count = 0;  // lanes holding a contact; the rest are padding
  // The candidate, its particle and wall, and its place in the thread's step list.
  std::uint32_t k[lanes], i[lanes], wall[lanes], entry[lanes];
  const typename M::Params* params[lanes];  // each lane's law
  // Gathered: the surface's velocity less the particle's, the particle's spin
  // (2D: wz alone) and radius, the lever of the reaction about the wall's axis.
  alignas(64) double vx[lanes], vy[lanes], vz[lanes];
  alignas(64) double wx[lanes], wy[lanes], wz[lanes];
  alignas(64) double r[lanes];
  alignas(64) double lever_x[lanes], lever_y[lanes], lever_z[lanes];
  // Results: the total force on the particle, its torque (2D: tz alone).
  alignas(64) double fx[lanes], fy[lanes], fz[lanes];
  alignas(64) double tx[lanes], ty[lanes], tz[lanes];

  // Lane l from a contact whose geometry the wall gave: the normal n (towards
  // the particle), the overlap, the surface velocity, the lever, R*.
  void gather_lane(int l, const V& n, double overlap, const V& surface_velocity, const V& v_i,
                   const S& w_i, double radius, double inv_mass, double effective_radius,
                   const V& lever, const History& h) {
    const V v_rel = surface_velocity - v_i;
    c.nx[l] = n[0], c.ny[l] = n[1];
    vx[l] = v_rel[0], vy[l] = v_rel[1];
    lever_x[l] = lever[0], lever_y[l] = lever[1];
    if constexpr (D == 3) {
      c.nz[l] = n[2], vz[l] = v_rel[2], lever_z[l] = lever[2];
      wx[l] = w_i[0], wy[l] = w_i[1], wz[l] = w_i[2];
    } else {
      wz[l] = w_i;
    }
    c.overlap[l] = overlap;
    r[l] = radius;
    c.inv_mass_sum[l] = inv_mass;
    c.effective_radius[l] = effective_radius;
    history.load(l, h);
  }

  // A harmless contact in the unused lanes (half a metre clear of its wall, at rest).
  void pad() {
    for (int l = count; l < lanes; ++l) {
      c.nx[l] = 1, c.ny[l] = 0;
      vx[l] = vy[l] = 0;
      wz[l] = 0;
      if constexpr (D == 3) c.nz[l] = 0, vz[l] = 0, wx[l] = wy[l] = 0;
      c.overlap[l] = -0.5;
      r[l] = 0.25;
      c.inv_mass_sum[l] = 1;
      c.effective_radius[l] = 0.25;
      params[l] = params[0];  // count > 0 when a batch is computed
      history.pad(l);
    }
  }

  // The per-contact path's kinematics lane by lane: the normal velocity and
  // Eq. 3.10's tangential slip velocity of the surface relative to the
  // particle's surface, v_rel - n (v_rel . n) + (r - a) (w x n) at the wall's
  // surface; in 2D its component along t = (-n_y, n_x).
  void kinematics() {
    for (int l = 0; l < lanes; ++l) {
      const double nx = c.nx[l], ny = c.ny[l];
      const double lever = r[l] - c.overlap[l];
      if constexpr (D == 3) {
        const double nz = c.nz[l];
        const double vn = vx[l] * nx + vy[l] * ny + vz[l] * nz;
        c.normal_velocity[l] = vn;
        c.vtx[l] = (vx[l] - nx * vn) + lever * (wy[l] * nz - wz[l] * ny);
        c.vty[l] = (vy[l] - ny * vn) + lever * (wz[l] * nx - wx[l] * nz);
        c.vtz[l] = (vz[l] - nz * vn) + lever * (wx[l] * ny - wy[l] * nx);
      } else {
        const double vn = vx[l] * nx + vy[l] * ny;
        c.normal_velocity[l] = vn;
        const double tvx = (vx[l] - nx * vn) + lever * (-wz[l] * ny);
        const double tvy = (vy[l] - ny * vn) + lever * (wz[l] * nx);
        c.tangential_velocity[l] = tvx * -ny + tvy * nx;
      }
    }
  }

  // The total force on the particle and its torque, the force applied at the
  // wall's surface (lever -(r - a) n from the centre).
  void totals() {
    for (int l = 0; l < lanes; ++l) {
      const double nx = c.nx[l], ny = c.ny[l], n_force = c.normal_force[l];
      const double arm = -(r[l] - c.overlap[l]);
      const double ax = arm * nx, ay = arm * ny;
      if constexpr (D == 3) {
        const double nz = c.nz[l], az = arm * nz;
        const double ftx = c.ftx[l], fty = c.fty[l], ftz = c.ftz[l];
        fx[l] = n_force * nx + ftx;
        fy[l] = n_force * ny + fty;
        fz[l] = n_force * nz + ftz;
        tx[l] = ay * ftz - az * fty;
        ty[l] = az * ftx - ax * ftz;
        tz[l] = ax * fty - ay * ftx;
      } else {
        const double t_force = c.tangential_force[l];
        const double ftx = t_force * -ny, fty = t_force * nx;
        fx[l] = n_force * nx + ftx;
        fy[l] = n_force * ny + fty;
        tz[l] = ax * fty - ay * ftx;
      }
    }
  }

  V total(int l) const { return lane_vector(fx, fy, fz, l); }
  S torque(int l) const {
    if constexpr (D == 3)
      return lane_vector(tx, ty, tz, l);
    else
      return tz[l];
  }
  V lever(int l) const { return lane_vector(lever_x, lever_y, lever_z, l); }
  // For the contact log.
  V normal(int l) const {
    if constexpr (D == 3)
      return lane_vector(c.nx, c.ny, c.nz, l);
    else
      return lane_vector(c.nx, c.ny, nullptr, l);
  }
  V tangential_force(int l) const {
    if constexpr (D == 3)
      return lane_vector(c.ftx, c.fty, c.ftz, l);
    else
      return V(-c.tangential_force[l] * c.ny[l], c.tangential_force[l] * c.nx[l]);
  }

 private:
  // Lane l of three lane arrays as a vector (2D: the first two).
  static V lane_vector(const double* x, const double* y, const double* z, int l) {
    if constexpr (D == 3)
      return V(x[l], y[l], z[l]);
    else
      return V(x[l], y[l]);
  }
};

}  // namespace granule
