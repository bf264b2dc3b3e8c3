// pairs() in an order fixed by the keys themselves.
//
// Lua 5.4 seeds its string hashes from addresses and the time at start-up
// (luai_makeseed), so the order in which `next` visits a table's string keys
// changes from one process to the next. A scene that fills one group per key
// of a table, in pairs() order, would then make its particles in another order
// each run (and a restart would replay its calls in another order than the
// run that wrote the checkpoint). Granule's pairs() visits numbers first (by
// value), then false, true, then strings (by their bytes), then keys of other
// types (tables, functions, userdata: in `next` order, which no program can
// fix). A table with a __pairs metamethod is iterated by it, as Lua does.
#pragma once

struct lua_State;

namespace granule::lua {

// Pushes a new sequence of the keys of the table at `index`, in the order above.
void push_ordered_keys(lua_State* L, int index);
// Replaces the global pairs with the ordered one.
void open_ordered_pairs(lua_State* L);

}  // namespace granule::lua
