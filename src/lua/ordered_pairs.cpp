#include "lua/ordered_pairs.hpp"

#include <algorithm>
#include <cstring>
#include <lua.hpp>
#include <string_view>
#include <vector>

namespace granule::lua {

namespace {

struct KeyRank {
  int group;             // 0 number, 1 boolean, 2 string, 3 any other type
  bool integer = false;  // a number key: lua_Integer (else a float)
  lua_Integer i = 0;
  lua_Number x = 0;
  std::string_view text;  // a string key (the table keeps the string alive)
  lua_Integer position;   // in `next` order: ties of group 3
};

bool number_less(const KeyRank& a, const KeyRank& b) {
  if (a.integer && b.integer) return a.i < b.i;
  const lua_Number xa = a.integer ? static_cast<lua_Number>(a.i) : a.x;
  const lua_Number xb = b.integer ? static_cast<lua_Number>(b.i) : b.x;
  if (xa != xb) return xa < xb;
  // Equal as floats: an integer and a float of the same value are not the same key
  // (2^53 + 1 and 2^53.0); the integer goes first, integers by their exact value.
  if (a.integer != b.integer) return a.integer;
  return false;
}

bool key_less(const KeyRank& a, const KeyRank& b) {
  if (a.group != b.group) return a.group < b.group;
  switch (a.group) {
    case 0:
      return number_less(a, b);
    case 1:
      return a.i < b.i;
    case 2:
      return a.text < b.text;
    default:
      return a.position < b.position;
  }
}

// upvalue 1: the ordered keys; upvalue 2: how many have been handed out.
int ordered_next(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_Integer at = lua_tointeger(L, lua_upvalueindex(2));
  for (;;) {
    ++at;
    if (lua_rawgeti(L, lua_upvalueindex(1), at) == LUA_TNIL) return 1;  // the end: nil
    lua_pushvalue(L, -1);
    // A key whose field the loop set to nil is no longer in the table (`next` skips it too).
    if (lua_rawget(L, 1) != LUA_TNIL) {
      lua_pushinteger(L, at);
      lua_replace(L, lua_upvalueindex(2));
      return 2;
    }
    lua_pop(L, 2);
  }
}

// Whether the keys of the table at `index` are exactly 1..#t: that order is already
// fixed by the keys, and the walk needs neither a list of them nor a sort.
bool is_sequence(lua_State* L, int index, lua_Integer& n) {
  n = static_cast<lua_Integer>(lua_rawlen(L, index));
  lua_Integer count = 0;
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    lua_pop(L, 1);
    const lua_Integer k = lua_isinteger(L, -1) ? lua_tointeger(L, -1) : 0;
    if (k < 1 || k > n) {
      lua_pop(L, 1);
      return false;
    }
    ++count;
  }
  return count == n;
}

// upvalue 1: the last index handed out; upvalue 2: the sequence's length at the start.
int sequence_next(lua_State* L) {
  luaL_checktype(L, 1, LUA_TTABLE);
  const lua_Integer n = lua_tointeger(L, lua_upvalueindex(2));
  for (lua_Integer at = lua_tointeger(L, lua_upvalueindex(1)) + 1; at <= n; ++at) {
    if (lua_rawgeti(L, 1, at) != LUA_TNIL) {  // a field the loop set to nil is skipped
      lua_pushinteger(L, at);
      lua_copy(L, -1, lua_upvalueindex(1));
      lua_insert(L, -2);
      return 2;
    }
    lua_pop(L, 1);
  }
  lua_pushnil(L);
  return 1;
}

int ordered_pairs(lua_State* L) {
  luaL_checkany(L, 1);
  if (lua_gettop(L) > 1)
    return luaL_error(L, "pairs takes one table, got %d arguments", lua_gettop(L));
  if (luaL_getmetafield(L, 1, "__pairs") != LUA_TNIL) {  // as Lua's own pairs
    lua_pushvalue(L, 1);
    lua_call(L, 1, 3);
    return 3;
  }
  luaL_checktype(L, 1, LUA_TTABLE);
  lua_Integer n = 0;
  if (is_sequence(L, 1, n)) {
    lua_pushinteger(L, 0);
    lua_pushinteger(L, n);
    lua_pushcclosure(L, sequence_next, 2);
  } else {
    push_ordered_keys(L, 1);
    lua_pushinteger(L, 0);
    lua_pushcclosure(L, ordered_next, 2);
  }
  lua_pushvalue(L, 1);
  lua_pushnil(L);
  return 3;
}

}  // namespace

void push_ordered_keys(lua_State* L, int index) {
  index = lua_absindex(L, index);
  lua_newtable(L);  // the keys in `next` order
  const int found = lua_gettop(L);
  std::vector<KeyRank> ranks;
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    lua_pop(L, 1);
    KeyRank r{3, false, 0, 0, {}, static_cast<lua_Integer>(ranks.size() + 1)};
    switch (lua_type(L, -1)) {
      case LUA_TNUMBER:
        r.group = 0;
        r.integer = lua_isinteger(L, -1);
        if (r.integer)
          r.i = lua_tointeger(L, -1);
        else
          r.x = lua_tonumber(L, -1);
        break;
      case LUA_TBOOLEAN:
        r.group = 1;
        r.i = lua_toboolean(L, -1);
        break;
      case LUA_TSTRING: {
        // lua_tolstring on a string key does not change it (only numbers are converted).
        std::size_t n = 0;
        const char* s = lua_tolstring(L, -1, &n);
        r.group = 2;
        r.text = std::string_view(s, n);
        break;
      }
      default:
        break;
    }
    lua_pushvalue(L, -1);
    lua_rawseti(L, found, r.position);
    ranks.push_back(r);
  }
  std::stable_sort(ranks.begin(), ranks.end(), key_less);
  lua_createtable(L, static_cast<int>(ranks.size()), 0);
  for (std::size_t k = 0; k < ranks.size(); ++k) {
    lua_rawgeti(L, found, ranks[k].position);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_remove(L, found);
}

void open_ordered_pairs(lua_State* L) {
  lua_pushcfunction(L, ordered_pairs);
  lua_setglobal(L, "pairs");
}

}  // namespace granule::lua
