// A value a binding has already printed (sim:table's text, sim:plot's file name):
// the REPL, which prints what a line returns, does not print it a second time.
#pragma once

#include <lua.hpp>

namespace granule::lua {

inline constexpr const char* shown_key = "granule.shown";

// Marks the value on the stack top as printed.
inline void mark_shown(lua_State* L) {
  lua_pushvalue(L, -1);
  lua_setfield(L, LUA_REGISTRYINDEX, shown_key);
}

// Forgets any mark (before the REPL runs a line).
inline void clear_shown(lua_State* L) {
  lua_pushnil(L);
  lua_setfield(L, LUA_REGISTRYINDEX, shown_key);
}

// Whether the value at `index` is the one last marked.
inline bool is_shown(lua_State* L, int index) {
  index = lua_absindex(L, index);
  lua_getfield(L, LUA_REGISTRYINDEX, shown_key);
  const bool same = !lua_isnil(L, -1) && lua_rawequal(L, index, -1);
  lua_pop(L, 1);
  return same;
}

}  // namespace granule::lua
