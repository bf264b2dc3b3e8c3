// Tab completion at the REPL prompt, from the live Lua state: global names and
// keywords (sim -> simulation, simulations), fields of tables (granule.vec.n ->
// granule.vec.norm) and methods of objects (sim:ru -> sim:run). Only raw reads:
// completing must never run a metamethod (strict globals, a simulation's
// "no such method" error) or change the state.
#pragma once

#include <string>
#include <vector>

struct lua_State;

namespace granule::lua {

// Full replacements for `word` (the text before the cursor back to the last
// character that cannot be part of a name path), sorted, without duplicates.
std::vector<std::string> complete(lua_State* L, const std::string& word);

}  // namespace granule::lua
