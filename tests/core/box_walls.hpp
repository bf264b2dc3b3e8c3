// Plane walls around [0, side] x ... x [0, height] (the last axis: z in 3D,
// y in 2D), facing in, of one material: the closed box the engine tests fill.
#pragma once

#include <string>

#include "engine/simulation.hpp"

namespace granule::test {

template <int D>
void add_box_walls(Simulation<D>& sim, double side, double height, int material) {
  for (int axis = 0; axis < D; ++axis) {
    WallSpec lo, hi;
    lo.name = "lo" + std::to_string(axis), hi.name = "hi" + std::to_string(axis);
    lo.material = hi.material = material;
    Triple n{0, 0, 0};
    n[axis] = 1;
    lo.normal = n;
    n[axis] = -1;
    hi.normal = n;
    hi.point = {0, 0, 0};
    hi.point[axis] = axis == D - 1 ? height : side;
    sim.add_wall(lo), sim.add_wall(hi);
  }
}

// Plane walls at 0 and `width` across each axis from `first_axis` on (a
// periodic axis before it stays open), facing in, of one material.
template <int D>
void add_walls_across(Simulation<D>& sim, int first_axis, double width, int material) {
  for (int axis = first_axis; axis < D; ++axis) {
    WallSpec lo, hi;
    lo.name = "lo" + std::to_string(axis), hi.name = "hi" + std::to_string(axis);
    lo.material = hi.material = material;
    lo.normal = hi.normal = {0, 0, 0};
    lo.normal[axis] = 1, hi.normal[axis] = -1;
    hi.point[axis] = width;
    sim.add_wall(lo), sim.add_wall(hi);
  }
}

}  // namespace granule::test
