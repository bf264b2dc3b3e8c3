// Checks that stop a run which has gone wrong, naming the step, the particle
// and what it touched, before the state written with the failure is useless.
// A NaN is caught in integrate() (simulation.cpp); an escape here.
#include <fmt/format.h>

#include "core/simulation.hpp"

namespace granule {

// A particle whose centre lies more than its radius beyond a wall (an overlap
// above twice its radius) has tunnelled through it: it crossed the wall within
// one step, or was driven through by a contact far stiffer or faster than the
// time step resolves. Walls are half-spaces, so the contact law would now push
// it back with a force far outside its range, creating energy: stop instead.
// (A centre just past the wall is a hard impact, not an escape: the overlapping
// fills of SPEC 2 throw particles at the chamber that hard in their first steps.)
// Called at every list rebuild, which a fast particle triggers within half a
// skin of travel; the cost is one clearance per particle and wall per rebuild,
// as much as listing the wall contacts.
template <int D>
void Simulation<D>::check_escapes() {
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const Wall<D>& wall = walls_[w];
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (p_.fixed[i]) continue;
      const double c = wall.clearance(p_.position[i], p_.radius[i]);
      if (!(c + 2 * p_.radius[i] < 0)) continue;
      const Triple x = to_triple(p_.position[i]), v = to_triple(p_.velocity[i]);
      fail(fmt::format(
          "step {} (t = {:.6g} s): particle {} (radius {:.4g} m) escaped through wall '{}' (its "
          "centre is {:.4g} m beyond it; position ({:.6g}), velocity ({:.6g}) m/s): it moved too "
          "far in one step for "
          "the wall contact to stop it; reduce time_step or raise the skin; the output keeps "
          "this state",
          step_, time_, p_.id[i], p_.radius[i], wall.name, -(c + p_.radius[i]),
          fmt::join(x.begin(), x.begin() + D, ", "), fmt::join(v.begin(), v.begin() + D, ", ")));
    }
  }
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
