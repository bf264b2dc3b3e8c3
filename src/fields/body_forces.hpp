// Body forces: uniform gravity, and the "centripetal gravity" of the
// agglomerate preparation (dissertation 7.3), an acceleration of constant
// magnitude toward a point (in a periodic scene, toward the line through it along
// the periodic axis) whose strength the script changes during a run.
// Each is skipped entirely when it is off.
#pragma once

#include "core/particles.hpp"

namespace granule {

template <int D>
struct BodyForces {
  bool gravity_on = false;
  Vec<D> gravity = Vec<D>::Zero();  // m/s^2
  bool central_on = false;
  Vec<D> central_point = Vec<D>::Zero();
  double central_strength = 0;  // m/s^2 toward central_point
  // A periodic scene's axis (-1: none). A point does not repeat with the scene, so
  // there the field pulls towards the line through central_point along that axis:
  // the same in every period, continuous across the seam.
  int periodic_axis = -1;

  bool active() const { return gravity_on || (central_on && central_strength != 0); }

  // The body force on a free particle of mass m at x (called only when active()).
  Vec<D> force(double mass, const Vec<D>& x) const {
    Vec<D> f = Vec<D>::Zero();
    if (gravity_on) f += mass * gravity;
    if (central_on && central_strength != 0) {
      Vec<D> d = central_point - x;
      if (periodic_axis >= 0) d[periodic_axis] = 0;
      const double len = d.norm();
      if (len > 0) f += (mass * central_strength / len) * d;
    }
    return f;
  }
};

}  // namespace granule
