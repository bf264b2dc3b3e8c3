// Plane walls around [0, side] x ... x [0, height] (the last axis: z in 3D,
// y in 2D), facing in, of one material: the closed box the engine tests fill.
#pragma once

#include <string>

#include "engine/simulation.hpp"

namespace granule::test {

// The two plane walls across `axis`, at 0 and `width`, facing in.
template <int D>
void add_walls_at(Simulation<D>& sim, int axis, double width, int material) {
  WallSpec lo, hi;
  lo.name = "lo" + std::to_string(axis), hi.name = "hi" + std::to_string(axis);
  lo.material = hi.material = material;
  lo.normal = hi.normal = {0, 0, 0};
  lo.normal[axis] = 1, hi.normal[axis] = -1;
  hi.point = {0, 0, 0};
  hi.point[axis] = width;
  sim.add_wall(lo), sim.add_wall(hi);
}

template <int D>
void add_box_walls(Simulation<D>& sim, double side, double height, int material) {
  for (int axis = 0; axis < D; ++axis)
    add_walls_at(sim, axis, axis == D - 1 ? height : side, material);
}

// Walls at 0 and `width` across each axis from `first_axis` on (a periodic
// axis before it stays open).
template <int D>
void add_walls_across(Simulation<D>& sim, int first_axis, double width, int material) {
  for (int axis = first_axis; axis < D; ++axis) add_walls_at(sim, axis, width, material);
}

}  // namespace granule::test
