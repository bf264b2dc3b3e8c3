// What the binding files of a simulation share (lua_simulation.cpp holds the
// userdata and the method table; wrap_*.cpp files add methods to it).
#pragma once

struct lua_State;

namespace granule {
class SimulationBase;
}

namespace granule::lua {

// The simulation a method was called on (argument 1); throws std::runtime_error
// if it is not a simulation or has been closed.
SimulationBase& simulation_argument(lua_State* L);

int l_picture(lua_State* L);  // sim:picture { ... }, wrap_picture.cpp

}  // namespace granule::lua
