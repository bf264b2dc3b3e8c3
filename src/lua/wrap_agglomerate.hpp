// Simulation methods for agglomerate work (dissertation chapter 7): reloading a
// saved agglomerate, the contact graph and its breakage, and the velocity
// damping of the preparation protocol (lua/granule/agglomerate.lua). Each takes
// the simulation already checked by lua_simulation.cpp, runs inside its
// protect(), reads arguments from stack index 2 and may throw.
#pragma once

#include <lua.hpp>

#include "engine/simulation_base.hpp"

namespace granule::lua {

// sim:load_particles { file = "agg.h5", snapshot = -1, material_map = { saved = "current" },
//                      offset = {x, y[, z]}, velocity = {vx, vy[, vz]}, histories = true }
//   -> list of new ids, number of contact histories restored
int load_particles(lua_State* L, SimulationBase& sim);

// sim:save_contact_histories { file = "agg.h5", particles = | material = } -> number saved
// (the run's output closed: sim:close())
int save_contact_histories(lua_State* L, SimulationBase& sim);

// sim:bonds { particles = {ids} | material = "name" } -> { {a, b}, ... } (ids, a < b)
int bonds(lua_State* L, SimulationBase& sim);

// sim:fragments { particles = | material = } -> { count =, labels = { [id] = k },
//                                                 masses = {...}, members = {...} }
int fragments(lua_State* L, SimulationBase& sim);

// sim:breakage { initial_bonds = sim:bonds {...}, particles = | material =,
//                initial_mass = kg, initial_count = n, large = 0.1, debris = 0.025, fines = 0.002,
//                labels = false, graph = "contacts" | "surviving_bonds" }
//   -> damage and debris ratios, fragment counts
int breakage(lua_State* L, SimulationBase& sim);

// sim:scale_velocities { factor = f, spin_factor = f, particles = | material = }
int scale_velocities(lua_State* L, SimulationBase& sim);

}  // namespace granule::lua
