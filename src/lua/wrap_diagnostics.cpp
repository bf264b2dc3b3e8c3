// sim:diagnostic(name, { options }) and friends: attach the C++ diagnostics of
// src/hooks by name. Options arrive as a flat key -> value map: nested tables
// become dotted keys ("areas.inner"), lists of numbers become lists, lists of
// strings become comma-joined strings, booleans become 0/1.
#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <string>

#include "core/errors.hpp"
#include "hooks/diagnostic.hpp"
#include "lua/lua_simulation.hpp"
#include "lua/lua_util.hpp"

namespace granule::lua {

namespace {

void read_options(lua_State* L, int index, const std::string& prefix, DiagnosticOptions& o,
                  int depth) {
  if (depth > 8) throw InputError(fmt::format("{}: options nest too deeply", o.context()));
  index = lua_absindex(L, index);
  // Read raw, as every binding reads: a proxy's fields would read as absent.
  if (has_index_metamethod(L, index))
    throw InputError(
        fmt::format("{}: options{} must be a plain table, not one with an __index "
                    "metamethod",
                    o.context(), prefix.empty() ? "" : " '" + prefix + "'"));
  lua_Integer length = static_cast<lua_Integer>(lua_rawlen(L, index));
  // A sequence: all numbers -> a list; all strings -> a joined string; tables -> key.1, key.2...
  if (length > 0) {
    std::vector<double> numbers;
    std::string joined;
    int kinds = 0;  // 1 numbers, 2 strings, 4 tables
    for (lua_Integer k = 1; k <= length; ++k) {
      lua_rawgeti(L, index, k);
      int t = lua_type(L, -1);
      if (t == LUA_TNUMBER) {
        kinds |= 1;
        numbers.push_back(lua_tonumber(L, -1));
      } else if (t == LUA_TSTRING) {
        kinds |= 2;
        joined += (joined.empty() ? "" : ",") + std::string(lua_tostring(L, -1));
      } else if (t == LUA_TTABLE) {
        kinds |= 4;
        read_options(L, -1, prefix + "." + std::to_string(k), o, depth + 1);
      } else {
        lua_pop(L, 1);
        throw InputError(fmt::format("{}: '{}[{}]' has an unsupported type ({})", o.context(),
                                     prefix, k, type_name(L, -1)));
      }
      lua_pop(L, 1);
    }
    if (kinds != 1 && kinds != 2 && kinds != 4)
      throw InputError(
          fmt::format("{}: '{}' mixes numbers, strings and tables", o.context(), prefix));
    if (kinds == 1) o.lists[prefix] = numbers;
    if (kinds == 2) o.strings[prefix] = joined;
    return;
  }
  lua_pushnil(L);
  while (lua_next(L, index)) {
    if (lua_type(L, -2) != LUA_TSTRING) {
      lua_pop(L, 2);
      throw InputError(fmt::format("{}: option keys must be names", o.context()));
    }
    std::string key = lua_tostring(L, -2);
    if (!prefix.empty()) key = prefix + "." + key;
    switch (lua_type(L, -1)) {
      case LUA_TNUMBER:
        o.numbers[key] = lua_tonumber(L, -1);
        break;
      case LUA_TBOOLEAN:
        o.numbers[key] = lua_toboolean(L, -1) ? 1 : 0;
        break;
      case LUA_TSTRING:
        o.strings[key] = lua_tostring(L, -1);
        break;
      case LUA_TTABLE:
        read_options(L, -1, key, o, depth + 1);
        break;
      default: {
        std::string type = type_name(L, -1);
        lua_pop(L, 2);
        throw InputError(
            fmt::format("{}: option '{}' has an unsupported type ({})", o.context(), key, type));
      }
    }
    lua_pop(L, 1);
  }
}

// sim:diagnostic("wall_force", { wall = "inner_piece", window = 0.01 }) -> id
int l_diagnostic(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    std::string name = read_string(L, 2, "diagnostic: name");
    DiagnosticOptions options(fmt::format("diagnostic '{}'", name));
    if (!lua_isnoneornil(L, 3)) {
      if (!lua_istable(L, 3))
        throw InputError(fmt::format("diagnostic '{}': options must be a table", name));
      read_options(L, 3, "", options, 0);
    }
    lua_pushinteger(L, s.sim->attach_diagnostic(name, options));
    return 1;
  });
}

// A diagnostic id as the engine keeps it: one past an int names none (not id mod 2^32).
int read_diagnostic_id(lua_State* L) {
  const std::int64_t id = read_integer(L, 2, "diagnostic id");
  if (id < 0 || id > std::numeric_limits<int>::max())
    throw InputError(fmt::format("no diagnostic with id {}", id));
  return static_cast<int>(id);
}

// sim:diagnostic_results(id) -> { scalar = value, ..., array = { ... } }
int l_diagnostic_results(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    int id = read_diagnostic_id(L);
    auto scalars = s.sim->diagnostic_results(id);
    auto arrays = s.sim->diagnostic_arrays(id);
    lua_newtable(L);
    for (const auto& [k, v] : scalars) {
      lua_pushnumber(L, v);
      lua_setfield(L, -2, k.c_str());
    }
    for (const auto& [k, values] : arrays) {
      lua_createtable(L, static_cast<int>(values.size()), 0);
      for (std::size_t i = 0; i < values.size(); ++i) {
        lua_pushnumber(L, values[i]);
        lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
      }
      lua_setfield(L, -2, k.c_str());
    }
    return 1;
  });
}

int l_remove_diagnostic(lua_State* L) {
  return protect(L, [](lua_State* L) {
    LuaSim& s = self(L);
    s.sim->detach_diagnostic(read_diagnostic_id(L));
    return 0;
  });
}

}  // namespace

const luaL_Reg diagnostic_methods[] = {
    {"diagnostic", l_diagnostic},
    {"diagnostic_results", l_diagnostic_results},
    {"remove_diagnostic", l_remove_diagnostic},
    {nullptr, nullptr},
};

}  // namespace granule::lua
