// Scenes whose final state two ways of running them must agree on bit for bit
// (canonical order in any storage order, tests/core/test_canonical_order.cpp;
// the distributed step on any number of ranks, tests/parallel/mpi_distributed_test.cpp).
#pragma once

#include "box_walls.hpp"
#include "core/random.hpp"
#include "engine/simulation.hpp"

namespace granule::test {

// A 3D overlapping pile of 700 spheres in a box, falling onto its floor
// (linear law with friction; the batched kernel).
inline void dense_pile(Simulation<3>& sim) {
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  const ParamValues law{{"k_normal", 1e3}, {"restitution", 0.5}, {"friction", 0.4}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "w", "linear", law);
  const double side = 0.008, r = 0.4e-3;
  test::add_box_walls(sim, side, 0.02, 1);
  FillSpec pile;
  pile.shape = RegionShape::box;
  pile.lo = {0, 0, 0}, pile.hi = {side, side, 0.006};
  pile.count = 700;
  pile.radius_min = 0.8 * r, pile.radius_max = r;
  pile.material = 0;
  pile.seed = 5;
  pile.allow_overlap = true;
  sim.fill(pile);
  sim.set_gravity({0, 0, -9.81});
}

// A touching lattice of 216 sticky spheres squeezed together (JKR): they
// stick, pull and roll.
inline void jkr_agglomerate(Simulation<3>& sim) {
  sim.add_material({"gel", 1200, 1e7, 0.3, 0.5});
  sim.set_contact("gel", "gel", "thornton_jkr", {{"friction", 0.3}});
  Random rng(8);
  const double r = 0.1e-3;
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      for (int c = 0; c < 6; ++c) {
        ParticleSpec s;
        s.position = {a * 1.98 * r, b * 1.98 * r, c * 1.98 * r};
        s.radius = r * rng.uniform(0.95, 1.0);
        s.material = 0;
        for (int d = 0; d < 3; ++d) s.velocity[d] = rng.uniform(-0.05, 0.05);
        sim.add_particle(s);
      }
}

// A 2D overlapping pile of 500 discs in a box (Walton-Braun, the dissertation's law).
inline void walton_braun_pile(Simulation<2>& sim) {
  sim.add_material({"powder", 1200, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  const ParamValues wb{{"k_load", 2e4}, {"restitution", 0.8}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", wb);
  sim.set_contact("powder", "steel", "walton_braun", wb);
  test::add_box_walls(sim, 0.01, 0.02, 1);
  FillSpec f;
  f.shape = RegionShape::box;
  f.lo = {0, 0, 0}, f.hi = {0.01, 0.008, 0};
  f.count = 500;
  f.radius_min = 0.12e-3, f.radius_max = 0.16e-3;
  f.material = 0;
  f.seed = 4;
  f.allow_overlap = true;
  sim.fill(f);
  sim.set_gravity({0, -9.81, 0});
}

}  // namespace granule::test
