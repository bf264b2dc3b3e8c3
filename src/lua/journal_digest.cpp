// The digest of a journaled call's arguments (Journal::digest): what lets a restart
// tell a replayed call given other values from the call the first run made.
#include <cmath>
#include <cstdint>
#include <lua.hpp>
#include <unordered_map>

#include "core/fnv1a.hpp"
#include "lua/journal.hpp"  // IWYU pragma: associated
#include "lua/ordered_pairs.hpp"

namespace granule::lua {

namespace {

void add_byte(Fnv1a& f, unsigned char b) {
  f.add(&b, 1);
}

// Tables already digested, by the order they were met: a table given twice (or holding
// itself) counts by that number the second time, so the work stays the tables' size.
using Seen = std::unordered_map<const void*, std::uint64_t>;

void add_value(Fnv1a& f, lua_State* L, int index, Seen& seen, int depth) {
  index = lua_absindex(L, index);
  const int type = lua_type(L, index);
  add_byte(f, static_cast<unsigned char>('a' + type + 1));
  switch (type) {
    case LUA_TBOOLEAN:
      add_byte(f, lua_toboolean(L, index) ? 1 : 0);
      break;
    case LUA_TNUMBER: {
      // By value, as Lua compares numbers (5000 == 5000.0), and so as a restart compares
      // -D values: a parameter given as 5e3 where the first run took its default of 5000
      // is the same run.
      lua_Integer i = 0;
      const lua_Number x = lua_tonumber(L, index);
      const bool integral = lua_isinteger(L, index)
                                ? (i = lua_tointeger(L, index), true)
                                : x == std::floor(x) && lua_numbertointeger(x, &i);
      if (integral) {
        add_byte(f, 'i');
        f.add(&i, sizeof i);
      } else {
        f.add(&x, sizeof x);
      }
      break;
    }
    case LUA_TSTRING: {
      std::size_t n = 0;
      const char* s = lua_tolstring(L, index, &n);
      f.add(&n, sizeof n);
      f.add(s, n);
      break;
    }
    case LUA_TTABLE: {
      if (depth >= Journal::max_depth) break;  // nested deeper: its place counts, not its contents
      const auto [at, first_time] = seen.emplace(lua_topointer(L, index), seen.size());
      if (!first_time) {
        add_byte(f, '^');
        f.add(&at->second, sizeof at->second);
        break;
      }
      luaL_checkstack(L, 4, "journal: a call's arguments nest too deep");
      push_ordered_keys(L, index);
      const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
      // Keys that are tables, functions or userdata come in an order their addresses set,
      // which differs between processes: they count by their number alone.
      std::uint64_t by_address = 0;
      for (lua_Integer k = 1; k <= n; ++k) {
        const int key_type = lua_rawgeti(L, -1, k);
        if (key_type != LUA_TNUMBER && key_type != LUA_TSTRING && key_type != LUA_TBOOLEAN) {
          ++by_address;
          lua_pop(L, 1);
          continue;
        }
        add_value(f, L, -1, seen, depth + 1);
        lua_rawget(L, index);
        add_value(f, L, -1, seen, depth + 1);
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
      f.add(&by_address, sizeof by_address);
      add_byte(f, '}');
      break;
    }
    default:  // functions, userdata, threads: made anew by the replayed scene
      break;
  }
}

}  // namespace

std::uint64_t Journal::digest(lua_State* L, int first, int count) {
  Fnv1a f;
  Seen seen;
  for (int k = 0; k < count; ++k) add_value(f, L, first + k, seen, 0);
  return f.value();
}

}  // namespace granule::lua
