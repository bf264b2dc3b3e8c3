// The engine's side of a batch of 3D particle-pair contacts (contact_batch.hpp;
// 2D: pair_batch_2d.hpp):
// what the pair loop gathers per contact (in slot order), the geometry and
// the totals computed lane by lane (vector instructions), and the contacts'
// identities for adding the results back in slot order. Knows no contact law:
// the model's force_batch() runs between geometry() and totals().
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "core/particles.hpp"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
// Lanes gathered as whole vectors and turned into the lane arrays in
// registers (gather_lane, lanes_in, lanes_out); without AVX2 and FMA the pair loop
// stores each value into its lane array (the portable build).
#define GRANULE_BATCH_RECORDS 1
#else
#define GRANULE_BATCH_RECORDS 0
#endif

namespace granule {

// Does a model's batch history say its History is one row of four doubles
// (BatchHistory3::four_doubles, with column(q) its lane arrays)?
template <typename H, typename = void>
struct history_is_row : std::false_type {};
template <typename H>
struct history_is_row<H, std::enable_if_t<H::four_doubles>> : std::true_type {};

template <int D, typename M>
struct PairBatch;

template <typename M>
struct PairBatch<3, M> {
  static constexpr int lanes = batch_lanes;
  ContactBatch<3> c;
  typename M::BatchHistory3 history;
  int count = 0;  // lanes holding a contact; the rest are padding
  std::uint32_t k[lanes], i[lanes], j[lanes];
  const typename M::Params* params[lanes];  // each lane's law
  // Gathered: x_i - x_j, v_j - v_i, the spins, the radii.
  alignas(64) double dx[lanes], dy[lanes], dz[lanes];
  alignas(64) double vx[lanes], vy[lanes], vz[lanes];
  alignas(64) double wix[lanes], wiy[lanes], wiz[lanes];
  alignas(64) double wjx[lanes], wjy[lanes], wjz[lanes];
  alignas(64) double r_i[lanes], r_j[lanes];
  // Results: the force on i (j feels minus it) and the torques about each centre.
  alignas(64) double fx[lanes], fy[lanes], fz[lanes];
  alignas(64) double tix[lanes], tiy[lanes], tiz[lanes];
  alignas(64) double tjx[lanes], tjy[lanes], tjz[lanes];

  // The history: as one row of four doubles where the model's is
  // (history_is_row and this build's rows), else through the model's load/store.
#if GRANULE_BATCH_RECORDS
  static constexpr bool history_row = history_is_row<typename M::BatchHistory3>::value;
#else
  static constexpr bool history_row = false;
#endif
  using History3 = typename M::template History<3>;

  // Lane l from its contact: the two particles' position, velocity and spin
  // vectors, radii, 1/m_i + 1/m_j (or 1 when the law does not need it this
  // step: batch_needs_mass) and the contact's history.
  void gather_lane(int l, const Vec<3>& x_i, const Vec<3>& x_j, const Vec<3>& v_i,
                   const Vec<3>& v_j, const Vec<3>& w_i, const Vec<3>& w_j, double radius_i,
                   double radius_j, double inv_mass_sum, const History3& h) {
#if GRANULE_BATCH_RECORDS
    // Each vector read as four doubles (the arrays are readable 8 bytes past
    // their last element, hot_array.hpp) and each row stored whole.
    const __m256d ri = _mm256_set1_pd(radius_i), rj = _mm256_set1_pd(radius_j);
    const __m256d d = _mm256_sub_pd(_mm256_loadu_pd(x_i.data()), _mm256_loadu_pd(x_j.data()));
    const __m256d v = _mm256_sub_pd(_mm256_loadu_pd(v_j.data()), _mm256_loadu_pd(v_i.data()));
    _mm256_store_pd(row[l], _mm256_blend_pd(d, ri, 8));
    _mm256_store_pd(row[l] + 4, _mm256_blend_pd(v, rj, 8));
    _mm256_store_pd(row[l] + 8,
                    _mm256_blend_pd(_mm256_loadu_pd(w_i.data()), _mm256_set1_pd(inv_mass_sum), 8));
    _mm256_store_pd(row[l] + 12, _mm256_loadu_pd(w_j.data()));  // its fourth unread
    if constexpr (history_row)
      _mm256_store_pd(row[l] + 16, _mm256_loadu_pd(reinterpret_cast<const double*>(&h)));
    else
      history.load(l, h);
#else
    const Vec<3> d = x_i - x_j, v = v_j - v_i;
    dx[l] = d[0], dy[l] = d[1], dz[l] = d[2];
    vx[l] = v[0], vy[l] = v[1], vz[l] = v[2];
    wix[l] = w_i[0], wiy[l] = w_i[1], wiz[l] = w_i[2];
    wjx[l] = w_j[0], wjy[l] = w_j[1], wjz[l] = w_j[2];
    r_i[l] = radius_i, r_j[l] = radius_j;
    c.inv_mass_sum[l] = inv_mass_sum;
    history.load(l, h);
#endif
  }
  // Component `axis` of lane l's x_i - x_j, for the periodic wrap.
  double& separation(int l, int axis) {
#if GRANULE_BATCH_RECORDS
    return row[l][axis];
#else
    return axis == 0 ? dx[l] : axis == 1 ? dy[l] : dz[l];
#endif
  }

  // Before geometry(): the gathered rows into the lane arrays.
  void lanes_in() {
#if GRANULE_BATCH_RECORDS
    for (int l = 0; l < count; l += 4) {
      rows_to_lanes(l, 0, dx, dy, dz, r_i);
      rows_to_lanes(l, 1, vx, vy, vz, r_j);
      rows_to_lanes(l, 2, wix, wiy, wiz, c.inv_mass_sum);
      rows_to_lanes(l, 3, wjx, wjy, wjz, unread);
      if constexpr (history_row)
        rows_to_lanes(l, 4, history.column(0), history.column(1), history.column(2),
                      history.column(3));
    }
#endif
  }
  // After totals(): the results into rows, (force on i, 0), (torque on i, 0),
  // (torque on j, 0) and the history, so that each is added or stored whole.
  void lanes_out() {
#if GRANULE_BATCH_RECORDS
    for (int l = 0; l < count; l += 4) {
      lanes_to_rows(l, 0, fx, fy, fz, nullptr);
      lanes_to_rows(l, 1, tix, tiy, tiz, nullptr);
      lanes_to_rows(l, 2, tjx, tjy, tjz, nullptr);
      if constexpr (history_row)
        lanes_to_rows(l, 4, history.column(0), history.column(1), history.column(2),
                      history.column(3));
    }
#endif
  }
  // Lane l's updated history into its contact's.
  void store_history(int l, History3& h) const {
#if GRANULE_BATCH_RECORDS
    if constexpr (history_row) {
      _mm256_storeu_pd(reinterpret_cast<double*>(&h), _mm256_load_pd(row[l] + 16));
      return;
    }
#endif
    history.store(l, h);
  }

  // Lane l's results onto its particles: i feels the force, j minus it
  // (a + (-b) is a - b), each its own torque.
  void add_i(ForceTorque<3>& p, int l) const {
#if GRANULE_BATCH_RECORDS
    // Force and torque each as one vector (ForceTorque<3>: four doubles each,
    // the fourth staying 0 as the rows' fourth is 0).
    _mm256_store_pd(p.force.data(),
                    _mm256_add_pd(_mm256_load_pd(p.force.data()), _mm256_load_pd(row[l])));
    _mm256_store_pd(p.torque.data(),
                    _mm256_add_pd(_mm256_load_pd(p.torque.data()), _mm256_load_pd(row[l] + 4)));
#else
    p.force += force_on_i(l);
    p.torque += torque_on_i(l);
#endif
  }
  void add_j(ForceTorque<3>& p, int l) const {
#if GRANULE_BATCH_RECORDS
    _mm256_store_pd(p.force.data(),
                    _mm256_sub_pd(_mm256_load_pd(p.force.data()), _mm256_load_pd(row[l])));
    _mm256_store_pd(p.torque.data(),
                    _mm256_add_pd(_mm256_load_pd(p.torque.data()), _mm256_load_pd(row[l] + 8)));
#else
    p.force += Vec<3>(-force_on_i(l));
    p.torque += torque_on_j(l);
#endif
  }
#if GRANULE_BATCH_RECORDS
  Vec<3> force_on_i(int l) const {
    return Vec<3>(row[l][0], row[l][1], row[l][2]);
  }
  Vec<3> torque_on_i(int l) const {
    return Vec<3>(row[l][4], row[l][5], row[l][6]);
  }
  Vec<3> torque_on_j(int l) const {
    return Vec<3>(row[l][8], row[l][9], row[l][10]);
  }
#else
  Vec<3> force_on_i(int l) const {
    return Vec<3>(fx[l], fy[l], fz[l]);
  }
  Vec<3> torque_on_i(int l) const {
    return Vec<3>(tix[l], tiy[l], tiz[l]);
  }
  Vec<3> torque_on_j(int l) const {
    return Vec<3>(tjx[l], tjy[l], tjz[l]);
  }
#endif
  // For the contact log.
  Vec<3> normal(int l) const {
    return Vec<3>(c.nx[l], c.ny[l], c.nz[l]);
  }
  Vec<3> tangential_force(int l) const {
    return Vec<3>(c.ftx[l], c.fty[l], c.ftz[l]);
  }

  // A harmless contact in the unused lanes (separated by half a metre, at
  // rest), so that every batch runs the same full-width loops.
  void pad() {
    for (int l = count; l < lanes; ++l) {
      dx[l] = 1, dy[l] = dz[l] = 0;
      vx[l] = vy[l] = vz[l] = 0;
      wix[l] = wiy[l] = wiz[l] = 0;
      wjx[l] = wjy[l] = wjz[l] = 0;
      r_i[l] = r_j[l] = 0.25;
      c.inv_mass_sum[l] = 1;
      params[l] = params[0];  // count > 0 when a batch is computed
      history.pad(l);
    }
  }

  // The contact geometry of the pair loop's per-contact path, lane by lane:
  // the normal from j to i, the overlap, the normal velocity and Eq. 3.10's
  // tangential slip velocity of j's surface relative to i's at the contact
  // point (levers r - a/2, as the torques in totals()).
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
      const double overlap = (r_i[l] + r_j[l]) - dist;
      c.overlap[l] = overlap;
      if constexpr (uses_effective_radius<M>::value)
        c.effective_radius[l] = r_i[l] * r_j[l] / (r_i[l] + r_j[l]);
      const double vn = vx[l] * nx + vy[l] * ny + vz[l] * nz;
      c.normal_velocity[l] = vn;
      const double lever_i = r_i[l] - 0.5 * overlap, lever_j = r_j[l] - 0.5 * overlap;
      const double wx = lever_i * wix[l] + lever_j * wjx[l];
      const double wy = lever_i * wiy[l] + lever_j * wjy[l];
      const double wz = lever_i * wiz[l] + lever_j * wjz[l];
      c.vtx[l] = (vx[l] - nx * vn) + (wy * nz - wz * ny);
      c.vty[l] = (vy[l] - ny * vn) + (wz * nx - wx * nz);
      c.vtz[l] = (vz[l] - nz * vn) + (wx * ny - wy * nx);
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

 private:
#if GRANULE_BATCH_RECORDS
  // Per lane as gathered: rows of four doubles, (x_i - x_j, r_i),
  // (v_j - v_i, r_j), (w_i, 1/m_i + 1/m_j), (w_j, -) and the history;
  // after totals() the results in the first three rows and the history in its
  // own (lanes_out).
  alignas(64) double row[lanes][20];
  alignas(64) double unread[lanes];  // the fourth column of the w_j rows

  // A 4x4 transpose in registers: q_k's element m becomes q_m's element k.
  static void transpose(__m256d& q0, __m256d& q1, __m256d& q2, __m256d& q3) {
    const __m256d lo01 = _mm256_unpacklo_pd(q0, q1), hi01 = _mm256_unpackhi_pd(q0, q1);
    const __m256d lo23 = _mm256_unpacklo_pd(q2, q3), hi23 = _mm256_unpackhi_pd(q2, q3);
    q0 = _mm256_permute2f128_pd(lo01, lo23, 0x20);
    q1 = _mm256_permute2f128_pd(hi01, hi23, 0x20);
    q2 = _mm256_permute2f128_pd(lo01, lo23, 0x31);
    q3 = _mm256_permute2f128_pd(hi01, hi23, 0x31);
  }
  // Row r of lanes l..l+3 into out_q[l..l+3], q = 0..3 (lanes past count get
  // what pad() then overwrites).
  void rows_to_lanes(int l, int r, double* out0, double* out1, double* out2, double* out3) {
    __m256d q0 = _mm256_load_pd(row[l] + 4 * r), q1 = _mm256_load_pd(row[l + 1] + 4 * r);
    __m256d q2 = _mm256_load_pd(row[l + 2] + 4 * r), q3 = _mm256_load_pd(row[l + 3] + 4 * r);
    transpose(q0, q1, q2, q3);
    _mm256_store_pd(out0 + l, q0), _mm256_store_pd(out1 + l, q1);
    _mm256_store_pd(out2 + l, q2), _mm256_store_pd(out3 + l, q3);
  }
  // The inverse: in_q[l..l+3] into row r of lanes l..l+3 (no in3: zeros).
  void lanes_to_rows(int l, int r, const double* in0, const double* in1, const double* in2,
                     const double* in3) {
    __m256d q0 = _mm256_load_pd(in0 + l), q1 = _mm256_load_pd(in1 + l);
    __m256d q2 = _mm256_load_pd(in2 + l), q3 = in3 ? _mm256_load_pd(in3 + l) : _mm256_setzero_pd();
    transpose(q0, q1, q2, q3);
    _mm256_store_pd(row[l] + 4 * r, q0), _mm256_store_pd(row[l + 1] + 4 * r, q1);
    _mm256_store_pd(row[l + 2] + 4 * r, q2), _mm256_store_pd(row[l + 3] + 4 * r, q3);
  }
#endif
};

}  // namespace granule
