// Thornton's frictional elastic force() (thornton_elastic.hpp) for a batch of
// contacts (contact_batch.hpp): the same formulas in the same order, lane by
// lane, every branch of Eqs. 6.5-6.11 and of the Masing bookkeeping written as
// a select, so that the lanes run as vector instructions.
//
// How close to force(): in 3D every lane computes force()'s operations on the
// same values (rotate_lanes_onto_plane is rotate_onto_plane lane by lane), so
// the two are equal bit for bit but where the compiler fuses multiply-adds
// differently in the two loops (round-off). In 2D the same holds for the
// history, kept as the 2-vectors force() keeps; the batch gives the slip
// velocity and takes the force as their components along t = (-n_y, n_x),
// which the vectors force() is given and returns are to round-off. Two places
// turn that round-off into more: where theta^3 is round-off away from 0 (a
// contact sliding on: T at mu N of the step before, plus mu dN, is mu N),
// Eq. 6.7's cube root makes a round-off e into e^(1/3) in theta; and the
// Masing returns compare T with +-T* (or T**), which are equal where the cap
// put both at mu N, so round-off may choose the other branch than force()
// there: both answers are force()'s for inputs a few ulp apart.
// tests/contact/test_batch_lanes.cpp checks both bounds.
//
// Eq. 6.7's cube root has no vector form in the maths library: each batch
// computes the cubes in one loop over the lanes, their roots one lane at a
// time, and the rest of the law in a third loop. GCC 12 vectorises the first
// and third, in 3D and 2D (the 2D first loop only as long as it reads T's
// components from registers, not back from the arrays it just stored them
// in: a select between such a load and another value defeats its
// if-conversion, and the loop stays scalar).
#pragma once

#include <cmath>
#include <type_traits>

#include "contact/contact_batch.hpp"
#include "contact/thornton_elastic.hpp"

namespace granule {

// One law for all lanes: its values in registers.
template <>
struct ThorntonElastic::LaneParams<true> {
  double hertz_, shear_, mu_;  // 4/3 E* (Eq. 6.3), 8 G* (no-slip stiffness 8 G* a), mu
  bool shrink_;                // shrink_rescale
  explicit LaneParams(const Params* const lane[]) {
    const Params& p = *lane[0];
    hertz_ = 4.0 / 3.0 * p.e_star, shear_ = 8 * p.g_star, mu_ = p.friction;
    shrink_ = p.shrink_rescale;
  }
  double hertz(int) const { return hertz_; }
  double shear(int) const { return shear_; }
  double mu(int) const { return mu_; }
  bool shrink(int) const { return shrink_; }
  bool any_shrink() const { return shrink_; }
};

// Lanes under different laws (material pairs): each value as an array over the lanes.
template <>
struct ThorntonElastic::LaneParams<false> {
  static constexpr int L = batch_lanes;
  alignas(64) double hertz_[L], shear_[L], mu_[L];
  bool shrink_[L];
  bool any_shrink_ = false;
  explicit LaneParams(const Params* const lane[]) {
    for (int l = 0; l < L; ++l) {
      const Params& p = *lane[l];
      hertz_[l] = 4.0 / 3.0 * p.e_star, shear_[l] = 8 * p.g_star, mu_[l] = p.friction;
      shrink_[l] = p.shrink_rescale;
      any_shrink_ = any_shrink_ || p.shrink_rescale;
    }
  }
  double hertz(int l) const { return hertz_[l]; }
  double shear(int l) const { return shear_[l]; }
  double mu(int l) const { return mu_[l]; }
  bool shrink(int l) const { return shrink_[l]; }
  bool any_shrink() const { return any_shrink_; }
};

namespace thornton_elastic_lanes {

constexpr double loading = ThorntonElastic::loading, unloading = ThorntonElastic::unloading,
                 reloading = ThorntonElastic::reloading;

// Eqs. 6.3-6.4 for lane l as force() computes them: N, and for the tangential
// increment the no-slip stiffness k0 = 8 G* a, mu N and mu dN (dN from the
// last step's N; 0 before the first). Not a number where the lanes do not
// touch (a padded lane): the caller selects those away.
template <typename P, typename Batch>
inline double normal_force(const P& q, const Batch& c, int l, double previous_normal, double& k0,
                           double& mu_n, double& mu_dn) {
  const double alpha = c.overlap[l];
  const double a = std::sqrt(alpha * c.effective_radius[l]);  // Eq. 6.4
  const double normal = q.hertz(l) * a * alpha;               // Eq. 6.3
  const double mu = q.mu(l);
  k0 = q.shear(l) * a;
  mu_n = mu * normal;
  mu_dn = mu * (normal - previous_normal);
  return normal;
}

// Eq. 6.7 for one lane: -1 where the increment does not slip (theta = 1:
// |dT| < mu dN), else theta^3 from Eqs. 6.8-6.10 read along u
// (mindlin_deresiewicz()) on the branch the increment follows, clamped to [0, 1].
inline double cube_of_theta(double branch, double t_u, double star_u, double star2_u, double mu_n,
                            double mu_dn, double k0, double slip_mag) {
  const bool virgin = branch == loading;
  const double back = branch == unloading ? star_u : star2_u;  // T* (6.9) or T** (6.10)
  const double num = virgin ? t_u + mu_dn : t_u - back + 2 * mu_dn;
  const double den = virgin ? mu_n : 2 * mu_n;
  double cube = 1 - num / den;
  cube = cube < 0 ? 0.0 : (cube > 1 ? 1.0 : cube);
  return k0 * slip_mag < mu_dn ? -1.0 : cube;
}

// shrink_rescale (mindlin_deresiewicz()): where a lane's law asks for it and N
// falls, `shrink` = a / a_prev = (N / N_prev)^(1/3) and `still` = 1 (its mu dN is
// then taken as 0); elsewhere 1 and 0. The roots in a loop of their own, as theta's.
// Returns whether any lane's law asks for it (else the lanes need no scaling).
template <typename P, typename Batch, typename History>
inline bool shrink_ratios(const P& q, const Batch& c, const History& h, double* shrink,
                          double* still) {
  if (!q.any_shrink()) {
    for (int l = 0; l < batch_lanes; ++l) shrink[l] = 1.0, still[l] = 0.0;
    return false;
  }
  for (int l = 0; l < batch_lanes; ++l) {
    double k0, mu_n, mu_dn;
    normal_force(q, c, l, h.previous_normal[l], k0, mu_n, mu_dn);
    const bool on = q.shrink(l) && mu_dn < 0 && mu_n > 0 && c.overlap[l] > 0;
    shrink[l] = on ? mu_n / (mu_n - mu_dn) : 1.0;
    still[l] = on ? 1.0 : 0.0;
  }
  for (int l = 0; l < batch_lanes; ++l) shrink[l] = std::cbrt(shrink[l]);
  return true;
}

// Theta lane by lane from cube_of_theta(): the cube root where the increment
// slips partially, 1 elsewhere.
inline void roots(const double* cube, double* theta) {
  for (int l = 0; l < batch_lanes; ++l) theta[l] = cube[l] < 0 ? 1.0 : std::cbrt(cube[l]);
}

// The branch after this increment's reversal (if any) and Masing's returns to
// loading, and the reversal points T* (reversal while loading or reloading)
// and T** (while unloading) set to T where the displacement turned.
inline double next_branch(double branch, bool moving, bool first, bool reversed, bool& to_unloading,
                          bool& to_reloading) {
  branch = moving && first ? loading : branch;  // the first increment of the contact loads
  to_reloading = reversed && branch == unloading;
  to_unloading = reversed && !(branch == unloading);
  return to_reloading ? reloading : (to_unloading ? unloading : branch);
}

template <typename P>
inline void lanes_3d(const P& q, ThorntonElastic::BatchHistory3& h, ContactBatch<3>& c) {
  constexpr int L = batch_lanes;
  const double dt = c.dt;
  // Carry T, T*, T** and u onto the current tangent plane (Eqs. 3.7-3.8).
  alignas(64) double tx[L], ty[L], tz[L], rx[L], ry[L], rz[L], r2x[L], r2y[L], r2z[L];
  alignas(64) double pux[L], puy[L], puz[L];
  rotate_lanes_onto_plane(c, h.tx, h.ty, h.tz, tx, ty, tz);
  rotate_lanes_onto_plane(c, h.rx, h.ry, h.rz, rx, ry, rz);
  rotate_lanes_onto_plane(c, h.qx, h.qy, h.qz, r2x, r2y, r2z);
  rotate_lanes_onto_plane(c, h.ux, h.uy, h.uz, pux, puy, puz);
  // What the first loop leaves for the last: u, the slip perpendicular to T's
  // line, |slip along it|, k0, mu N, mu dN; and for the roots the cubes.
  alignas(64) double ux[L], uy[L], uz[L], px[L], py[L], pz[L], par[L];
  alignas(64) double k0s[L], mu_ns[L], mu_dns[L], cube[L], theta[L], shrink[L], still[L];
  // shrink_rescale: T, T*, T** with the contact radius (and dN taken as 0, below).
  if (shrink_ratios(q, c, h, shrink, still))
    for (int l = 0; l < L; ++l) {
      const double sh = shrink[l];
      tx[l] *= sh, ty[l] *= sh, tz[l] *= sh, rx[l] *= sh, ry[l] *= sh, rz[l] *= sh;
      r2x[l] *= sh, r2y[l] *= sh, r2z[l] *= sh;
    }
  for (int l = 0; l < L; ++l) {
    double k0, mu_n, mu_dn;
    const double normal = normal_force(q, c, l, h.previous_normal[l], k0, mu_n, mu_dn);
    mu_dn = still[l] != 0 ? 0.0 : mu_dn;
    // No overlap (force() clears the history there; the engine only passes
    // contacts that touch, and padded lanes): N = 0, and mu N = 0 clears the rest.
    const bool touching = c.overlap[l] > 0;
    c.normal_force[l] = touching ? normal : 0.0;
    h.previous_normal[l] = touching ? normal : 0.0;
    mu_n = touching ? mu_n : 0.0;
    const double sx = c.vtx[l] * dt, sy = c.vty[l] * dt, sz = c.vtz[l] * dt;  // Eq. 3.10
    const double t_mag = std::sqrt(tx[l] * tx[l] + ty[l] * ty[l] + tz[l] * tz[l]);
    const double slip_mag = std::sqrt(sx * sx + sy * sy + sz * sz);
    // T's line of action; for T = 0 the slip, and with no slip either the last sense.
    // (The last sense divided by 1, so that every lane divides: a division
    // under a condition keeps the loop from vectorising.)
    const bool has_t = t_mag > 0, has_slip = slip_mag > 0;
    const double mag = has_t ? t_mag : (has_slip ? slip_mag : 1.0);
    const double lx = (has_t ? tx[l] : (has_slip ? sx : pux[l])) / mag;
    const double ly = (has_t ? ty[l] : (has_slip ? sy : puy[l])) / mag;
    const double lz = (has_t ? tz[l] : (has_slip ? sz : puz[l])) / mag;
    const double slip_par = sx * lx + sy * ly + sz * lz;
    px[l] = sx - slip_par * lx, py[l] = sy - slip_par * ly, pz[l] = sz - slip_par * lz;
    par[l] = std::abs(slip_par);
    // u: the sense of this increment along the line; with no parallel slip
    // (only dN acts) the sense stays as it was.
    const double toward = pux[l] * lx + puy[l] * ly + puz[l] * lz;
    const double sense = slip_par > 0 ? 1.0 : (slip_par < 0 ? -1.0 : (toward < 0 ? -1.0 : 1.0));
    const double vx = sense * lx, vy = sense * ly, vz = sense * lz;
    ux[l] = vx, uy[l] = vy, uz[l] = vz;
    const bool moving = slip_par != 0;
    const bool first = pux[l] * pux[l] + puy[l] * puy[l] + puz[l] * puz[l] == 0;
    const bool reversed = moving && !first && vx * pux[l] + vy * puy[l] + vz * puz[l] < 0;
    bool to_unloading, to_reloading;
    double branch = next_branch(h.branch[l], moving, first, reversed, to_unloading, to_reloading);
    rx[l] = to_unloading ? tx[l] : rx[l], ry[l] = to_unloading ? ty[l] : ry[l];
    rz[l] = to_unloading ? tz[l] : rz[l];
    r2x[l] = to_reloading ? tx[l] : r2x[l], r2y[l] = to_reloading ? ty[l] : r2y[l];
    r2z[l] = to_reloading ? tz[l] : r2z[l];
    const double t_u = tx[l] * vx + ty[l] * vy + tz[l] * vz;
    const double star_u = rx[l] * vx + ry[l] * vy + rz[l] * vz;
    const double star2_u = r2x[l] * vx + r2y[l] * vy + r2z[l] * vz;
    // Masing's memory: back on the curve this branch branched off from.
    branch = branch == reloading && t_u >= star_u ? loading : branch;
    branch = branch == unloading && t_u >= -star_u ? loading : branch;
    h.branch[l] = mu_n > 0 ? branch : loading;
    cube[l] = cube_of_theta(branch, t_u, star_u, star2_u, mu_n, mu_dn, k0, slip_mag);
    k0s[l] = k0, mu_ns[l] = mu_n, mu_dns[l] = mu_dn;
  }
  roots(cube, theta);
  for (int l = 0; l < L; ++l) {
    const double k0 = k0s[l], mu_dn = mu_dns[l], th = theta[l];
    const double vx = ux[l], vy = uy[l], vz = uz[l];
    // Eqs. 6.5-6.6 along u; the perpendicular part of the increment does not slip.
    const double along = k0 * th * par[l] + mu_dn * (1 - th);
    double nx = tx[l] + along * vx + k0 * px[l], ny = ty[l] + along * vy + k0 * py[l],
           nz = tz[l] + along * vz + k0 * pz[l];
    // Eq. 6.11: the reversal points move outwards by mu dN (T* was reached moving
    // against u while unloading, along u while reloading; T** against u), on a
    // step that slips (mindlin_deresiewicz()).
    const double branch = h.branch[l];
    const bool un = branch == unloading && th < 1, re = branch == reloading && th < 1;
    double sx = un ? rx[l] - mu_dn * vx : (re ? rx[l] + mu_dn * vx : rx[l]);
    double sy = un ? ry[l] - mu_dn * vy : (re ? ry[l] + mu_dn * vy : ry[l]);
    double sz = un ? rz[l] - mu_dn * vz : (re ? rz[l] + mu_dn * vz : rz[l]);
    double s2x = re ? r2x[l] - mu_dn * vx : r2x[l];
    double s2y = re ? r2y[l] - mu_dn * vy : r2y[l];
    double s2z = re ? r2z[l] - mu_dn * vz : r2z[l];
    // |T| <= mu N; so are the reversal values (they are forces T once had).
    const double cap = mu_ns[l];
    auto cap_at = [cap](double& x, double& y, double& z) {
      const double sq = x * x + y * y + z * z;
      const bool over = sq > cap * cap;
      const double scale = cap / std::sqrt(sq);
      x = over ? x * scale : x, y = over ? y * scale : y, z = over ? z * scale : z;
    };
    cap_at(nx, ny, nz);
    cap_at(sx, sy, sz);
    cap_at(s2x, s2y, s2z);
    // No friction, or N = 0: |T| <= 0 and the history cleared. Else u kept
    // (unrotated) where this step had none.
    const bool free = !(cap > 0);
    h.tx[l] = free ? 0.0 : nx, h.ty[l] = free ? 0.0 : ny, h.tz[l] = free ? 0.0 : nz;
    h.rx[l] = free ? 0.0 : sx, h.ry[l] = free ? 0.0 : sy, h.rz[l] = free ? 0.0 : sz;
    h.qx[l] = free ? 0.0 : s2x, h.qy[l] = free ? 0.0 : s2y, h.qz[l] = free ? 0.0 : s2z;
    const bool new_u = vx * vx + vy * vy + vz * vz > 0;
    h.ux[l] = free ? 0.0 : (new_u ? vx : h.ux[l]);
    h.uy[l] = free ? 0.0 : (new_u ? vy : h.uy[l]);
    h.uz[l] = free ? 0.0 : (new_u ? vz : h.uz[l]);
    c.ftx[l] = free ? 0.0 : nx, c.fty[l] = free ? 0.0 : ny, c.ftz[l] = free ? 0.0 : nz;
  }
}

template <typename P>
inline void lanes_2d(const P& q, ThorntonElastic::BatchHistory2& h, ContactBatch<2>& c) {
  constexpr int L = batch_lanes;
  const double dt = c.dt;
  // T, T* and T** (after this step's reversal) on the line, u, the slip
  // across T's line (round-off), |slip along it|, k0, mu N, mu dN, and for the
  // roots the cubes.
  alignas(64) double tx[L], ty[L], rx[L], ry[L], r2x[L], r2y[L], ux[L], uy[L];
  alignas(64) double px[L], py[L], par[L], k0s[L], mu_ns[L], mu_dns[L], cube[L], theta[L];
  alignas(64) double shrink[L], still[L];
  shrink_ratios(q, c, h, shrink, still);
  for (int l = 0; l < L; ++l) {
    double k0, mu_n, mu_dn;
    const double normal = normal_force(q, c, l, h.previous_normal[l], k0, mu_n, mu_dn);
    mu_dn = still[l] != 0 ? 0.0 : mu_dn;  // shrink_rescale, as in 3D
    const double sh = shrink[l];
    const bool touching = c.overlap[l] > 0;  // as in 3D
    c.normal_force[l] = touching ? normal : 0.0;
    h.previous_normal[l] = touching ? normal : 0.0;
    mu_n = touching ? mu_n : 0.0;
    // rotate_onto_plane<2> (Eqs. 3.7-3.8): |old| along +t or -t, the side old
    // projects to, as the 2-vector force() forms.
    const double ax = -c.ny[l], ay = c.nx[l];  // t
    auto onto_line = [ax, ay](double ox, double oy) {
      const double old_sq = ox * ox + oy * oy;
      const double along = ox * ax + oy * ay;
      const double magnitude = std::sqrt(old_sq);
      const bool kept = old_sq > 0 && !(along * along <= 1e-30 * old_sq);
      return kept ? (along > 0 ? magnitude : -magnitude) : 0.0;
    };
    const double t = onto_line(h.tx[l], h.ty[l]), star = onto_line(h.rx[l], h.ry[l]);
    const double star2 = onto_line(h.qx[l], h.qy[l]), pu = onto_line(h.ux[l], h.uy[l]);
    const double t_x = t * ax * sh, t_y = t * ay * sh;  // used from registers below (see the top)
    tx[l] = t_x, ty[l] = t_y;
    double sx = star * ax * sh, sy = star * ay * sh, s2x = star2 * ax * sh, s2y = star2 * ay * sh;
    const double pux = pu * ax, puy = pu * ay;
    // d(delta), Eq. 3.10: the slip velocity along t as the vector force() is given.
    const double v_t = c.tangential_velocity[l];
    const double dx = v_t * ax * dt, dy = v_t * ay * dt;
    // From here force()'s 3D steps on 2-vectors (lanes_3d without z).
    const double t_mag = std::sqrt(t_x * t_x + t_y * t_y);
    const double slip_mag = std::sqrt(dx * dx + dy * dy);
    const bool has_t = t_mag > 0, has_slip = slip_mag > 0;
    const double mag = has_t ? t_mag : (has_slip ? slip_mag : 1.0);
    const double lx = (has_t ? t_x : (has_slip ? dx : pux)) / mag;
    const double ly = (has_t ? t_y : (has_slip ? dy : puy)) / mag;
    const double slip_par = dx * lx + dy * ly;
    px[l] = dx - slip_par * lx, py[l] = dy - slip_par * ly;
    par[l] = std::abs(slip_par);
    const double toward = pux * lx + puy * ly;
    const double sense = slip_par > 0 ? 1.0 : (slip_par < 0 ? -1.0 : (toward < 0 ? -1.0 : 1.0));
    const double vx = sense * lx, vy = sense * ly;
    ux[l] = vx, uy[l] = vy;
    const bool moving = slip_par != 0;
    const bool first = pux * pux + puy * puy == 0;
    const bool reversed = moving && !first && vx * pux + vy * puy < 0;
    bool to_unloading, to_reloading;
    double branch = next_branch(h.branch[l], moving, first, reversed, to_unloading, to_reloading);
    sx = to_unloading ? t_x : sx, sy = to_unloading ? t_y : sy;
    s2x = to_reloading ? t_x : s2x, s2y = to_reloading ? t_y : s2y;
    rx[l] = sx, ry[l] = sy, r2x[l] = s2x, r2y[l] = s2y;
    const double t_u = t_x * vx + t_y * vy;
    const double star_u = sx * vx + sy * vy, star2_u = s2x * vx + s2y * vy;
    // Masing's memory: back on the curve this branch branched off from.
    branch = branch == reloading && t_u >= star_u ? loading : branch;
    branch = branch == unloading && t_u >= -star_u ? loading : branch;
    h.branch[l] = mu_n > 0 ? branch : loading;
    cube[l] = cube_of_theta(branch, t_u, star_u, star2_u, mu_n, mu_dn, k0, slip_mag);
    k0s[l] = k0, mu_ns[l] = mu_n, mu_dns[l] = mu_dn;
  }
  roots(cube, theta);
  for (int l = 0; l < L; ++l) {
    const double k0 = k0s[l], mu_dn = mu_dns[l], th = theta[l];
    const double vx = ux[l], vy = uy[l];
    // Eqs. 6.5-6.6 along u; the part of the increment across T's line does not slip.
    const double along = k0 * th * par[l] + mu_dn * (1 - th);
    double nx = tx[l] + along * vx + k0 * px[l], ny = ty[l] + along * vy + k0 * py[l];
    // Eq. 6.11, as in 3D.
    const double branch = h.branch[l];
    const bool un = branch == unloading && th < 1, re = branch == reloading && th < 1;
    double sx = un ? rx[l] - mu_dn * vx : (re ? rx[l] + mu_dn * vx : rx[l]);
    double sy = un ? ry[l] - mu_dn * vy : (re ? ry[l] + mu_dn * vy : ry[l]);
    double s2x = re ? r2x[l] - mu_dn * vx : r2x[l];
    double s2y = re ? r2y[l] - mu_dn * vy : r2y[l];
    // |T|, |T*|, |T**| <= mu N.
    const double cap = mu_ns[l];
    auto cap_at = [cap](double& x, double& y) {
      const double sq = x * x + y * y;
      const bool over = sq > cap * cap;
      const double scale = cap / std::sqrt(sq);
      x = over ? x * scale : x, y = over ? y * scale : y;
    };
    cap_at(nx, ny);
    cap_at(sx, sy);
    cap_at(s2x, s2y);
    // Cleared without friction or N; u kept (unrotated) where this step had none.
    const bool free = !(cap > 0);
    h.tx[l] = free ? 0.0 : nx, h.ty[l] = free ? 0.0 : ny;
    h.rx[l] = free ? 0.0 : sx, h.ry[l] = free ? 0.0 : sy;
    h.qx[l] = free ? 0.0 : s2x, h.qy[l] = free ? 0.0 : s2y;
    const bool new_u = vx * vx + vy * vy > 0;
    h.ux[l] = free ? 0.0 : (new_u ? vx : h.ux[l]);
    h.uy[l] = free ? 0.0 : (new_u ? vy : h.uy[l]);
    // The force along t (the engine applies it along t).
    c.tangential_force[l] = free ? 0.0 : nx * -c.ny[l] + ny * c.nx[l];
  }
}

template <typename History, typename Batch>
inline void dispatch(const ThorntonElastic::Params* const lane[], History& h, Batch& c) {
  with_lane_params<ThorntonElastic>(lane, [&](const auto& q) {
    if constexpr (std::is_same_v<Batch, ContactBatch<2>>)
      lanes_2d(q, h, c);
    else
      lanes_3d(q, h, c);
  });
}

}  // namespace thornton_elastic_lanes

inline void ThorntonElastic::force_batch(const Params* const lane[], BatchHistory3& h,
                                         ContactBatch<3>& c) {
  thornton_elastic_lanes::dispatch(lane, h, c);
}
inline void ThorntonElastic::force_batch(const Params* const lane[], BatchHistory2& h,
                                         ContactBatch<2>& c) {
  thornton_elastic_lanes::dispatch(lane, h, c);
}

}  // namespace granule
