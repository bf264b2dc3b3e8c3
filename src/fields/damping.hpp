// Damping of the particles' motion as a whole, for quasi-static work (settling a
// bed, preparing an agglomerate) where the contacts' own dissipation is too slow
// or absent. Off unless a scene asks (sim:set_damping), and then applied in the
// integration (integrate/leapfrog.hpp) to every free particle:
//  - viscous: dv/dt = a - c v and dw/dt = alpha - c_w w, with rates c and c_w in
//    1/s (LAMMPS's fix viscous with gamma = c m, the same decay time for every
//    size). Stepped exactly for a force constant over the step:
//      v' = v e^{-c h} + a (1 - e^{-c h}) / c,
//    so a free particle decays as e^{-c t} and a falling one reaches g / c,
//    at any c h (no stability limit);
//  - local (Cundall's non-viscous damping, as PFC's and Yade's): each component
//    of the unbalanced force and torque reduced or raised by the fraction
//    alpha of its size, against the motion: F_k - alpha |F_k| sign(v_k), the
//    velocity taken when the force acts (v + a h / 2, the kick's middle). It damps
//    accelerations, not motion: a free particle flies on, a body at rest under
//    a load starts off at (1 - alpha) a, and a contact of restitution 1 rebounds
//    at sqrt((1 - alpha) / (1 + alpha)) of its approach speed.
#pragma once

#include <cmath>

namespace granule {

struct Damping {
  double viscous = 0;         // c, 1/s: dv/dt = -c v
  double spin = 0;            // c_w, 1/s: dw/dt = -c_w w
  double local_fraction = 0;  // alpha in [0, 1): Cundall's local damping

  bool active() const { return viscous != 0 || spin != 0 || local_fraction != 0; }
};

// What one step of length h applies: v' = v * keep + a * by.
struct DampingStep {
  double keep_v = 1, by_v = 0;  // translation
  double keep_w = 1, by_w = 0;  // rotation
  double local = 0;
  // Which motions it damps: the other takes the undamped update, the same bits
  // as without damping.
  bool translation = false, rotation = false;

  DampingStep(const Damping& d, double h) {
    set(d.viscous, h, keep_v, by_v);
    set(d.spin, h, keep_w, by_w);
    local = d.local_fraction;
    translation = d.viscous != 0 || local != 0;
    rotation = d.spin != 0 || local != 0;
  }
  // e^{-c h} and (1 - e^{-c h}) / c, the latter h where c h is 0 and without
  // the cancellation of 1 - e^{-c h} for small c h (expm1).
  static void set(double c, double h, double& keep, double& by) {
    keep = std::exp(-c * h);
    by = c * h > 0 ? -std::expm1(-c * h) / c : h;  // c h underflowing to 0: no damping
  }
  // Cundall's local damping of one component a_k of an acceleration, against
  // the motion v_k at the step's middle time.
  double local_factor(double a_k, double v_mid_k) const {
    const double s = a_k * v_mid_k;
    return s > 0 ? 1 - local : s < 0 ? 1 + local : 1.0;
  }
};

}  // namespace granule
