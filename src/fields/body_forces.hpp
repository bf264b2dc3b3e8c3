// Body forces: uniform gravity, and the "centripetal gravity" of the
// agglomerate preparation (dissertation 7.3), an acceleration of constant
// magnitude toward a point whose strength the script changes during a run.
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

  bool active() const { return gravity_on || (central_on && central_strength != 0); }

  void apply(Particles<D>& p) const {
    const std::size_t n = p.size();
    if (gravity_on) {
      for (std::size_t i = 0; i < n; ++i)
        if (!p.fixed[i]) p.force[i] += p.mass[i] * gravity;
    }
    if (central_on && central_strength != 0) {
      for (std::size_t i = 0; i < n; ++i) {
        if (p.fixed[i]) continue;
        Vec<D> d = central_point - p.position[i];
        double len = d.norm();
        if (len > 0) p.force[i] += (p.mass[i] * central_strength / len) * d;
      }
    }
  }
};

}  // namespace granule
