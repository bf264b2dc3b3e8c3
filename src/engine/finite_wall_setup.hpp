// Builds a finite wall (a rectangle, disk, tube or cone: geometry/finite_walls.hpp)
// from its specification, checking each parameter and naming the bad one.
#pragma once

#include <string>

#include "engine/simulation_base.hpp"
#include "geometry/walls.hpp"

namespace granule {

// The finite wall of `s` (name, type and material already checked by add_wall);
// `ctx` ("wall 'name'") starts every error message.
template <int D>
Wall<D> make_finite_wall(const WallSpec& s, const std::string& ctx);

}  // namespace granule
