// The Simulation userdata shared by the binding files (lua_simulation.cpp and
// the wrap_*.cpp files that add methods to it).
#pragma once

#include <lua.hpp>
#include <memory>

#include "core/simulation_base.hpp"
#include "io/run_output.hpp"

namespace granule::lua {

inline constexpr const char* simulation_metatable = "granule.Simulation";

struct LuaSim {
  std::unique_ptr<SimulationBase> sim;
  std::unique_ptr<io::RunOutput> output;
  int self_ref = LUA_NOREF;
  bool running = false;
  bool header_printed = false;
};

// The simulation at stack index 1; throws (use inside protect()) if it is not one.
LuaSim& self(lua_State* L);

// Methods added by wrap_diagnostics.cpp.
extern const luaL_Reg diagnostic_methods[];

}  // namespace granule::lua
