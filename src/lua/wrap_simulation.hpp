// The methods of the Simulation userdata, defined by topic in wrap_setup.cpp,
// wrap_run.cpp, wrap_output.cpp and wrap_queries.cpp and registered in one
// table in lua_simulation.cpp. Each reads its arguments from the Lua stack
// (the simulation at index 1) and runs inside protect().
#pragma once

#include <cstdint>
#include <lua.hpp>

#include "engine/simulation_base.hpp"
#include "lua/lua_simulation.hpp"

namespace granule::lua {

// The dimension of the simulation at index 1.
int dim(lua_State* L);
// The particle id at `index`; throws InputError when `sim` has no such particle.
std::int64_t particle_id(lua_State* L, int index, const SimulationBase& sim);

// wrap_setup.cpp
int l_material(lua_State* L);
int l_contact(lua_State* L);
int l_set_contact(lua_State* L);
int l_wall_plane(lua_State* L);
int l_wall_cylinder(lua_State* L);
int l_wall_mesh(lua_State* L);      // wrap_mesh.cpp
int l_wall_polyline(lua_State* L);  // wrap_polyline.cpp
int l_wall_disk(lua_State* L);
int l_wall_cone(lua_State* L);
int l_add_particle(lua_State* L);
int l_fill(lua_State* L);
int l_gravity(lua_State* L);
int l_set_damping(lua_State* L);
int l_damping(lua_State* L);
int l_central_field(lua_State* L);
int l_set_central_strength(lua_State* L);
int l_central_strength(lua_State* L);
int l_remove_central_field(lua_State* L);
int l_set_wall(lua_State* L);
int l_set_velocity(lua_State* L);
int l_set_position(lua_State* L);
int l_set_spin(lua_State* L);
int l_set_fixed(lua_State* L);
int l_remove_particle(lua_State* L);

// wrap_run.cpp
int l_run(lua_State* L);
int l_every(lua_State* L);
int l_remove_hook(lua_State* L);
int l_set(lua_State* L);
int l_prepare(lua_State* L);

// wrap_output.cpp
int l_output(lua_State* L);
int l_snapshot(lua_State* L);
int l_series(lua_State* L);
int l_append(lua_State* L);
int l_result(lua_State* L);
int l_close(lua_State* L);

// wrap_views.cpp
int l_arrays(lua_State* L);
int l_contact_arrays(lua_State* L);

// wrap_table_plot.cpp
int l_table(lua_State* L);
int l_plot(lua_State* L);

// wrap_queries.cpp
int l_wall(lua_State* L);
int l_particle(lua_State* L);
int l_particles(lua_State* L);
int l_stats(lua_State* L);
int l_contacts(lua_State* L);
int l_time(lua_State* L);
int l_step_count(lua_State* L);
int l_time_step(lua_State* L);
int l_time_step_rule(lua_State* L);
int l_describe(lua_State* L);
int l_timings(lua_State* L);
int l_dimension(lua_State* L);
int l_contact_parameters(lua_State* L);
int l_materials(lua_State* L);
int l_walls(lua_State* L);

// wrap_bonds.cpp
int l_bond(lua_State* L);
int l_bond_counts(lua_State* L);

}  // namespace granule::lua
