#include "lua/completion.hpp"

#include <algorithm>
#include <cctype>
#include <lua.hpp>

namespace granule::lua {

namespace {

const char* const keywords[] = {"and",   "break", "do",       "else", "elseif", "end",
                                "false", "for",   "function", "goto", "if",     "in",
                                "local", "nil",   "not",      "or",   "repeat", "return",
                                "then",  "true",  "until",    "while"};

bool is_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// Pushes the table whose keys are the fields (or, for ':', the methods) of the
// value on the stack top, replacing it: the value itself if it is a table, else
// its metatable's __index table; nil if there is none.
void push_fields(lua_State* L) {
  if (lua_type(L, -1) == LUA_TTABLE) return;
  if (!lua_getmetatable(L, -1)) {
    lua_pop(L, 1);
    lua_pushnil(L);
    return;
  }
  lua_pushstring(L, "__index");
  lua_rawget(L, -2);
  lua_remove(L, -2);  // metatable
  lua_remove(L, -2);  // value
  if (lua_type(L, -1) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_pushnil(L);
  }
}

// Adds the string keys of the table on the stack top (and of its metatable's
// __index table, one level) that start with `partial`.
void collect(lua_State* L, const std::string& partial, bool functions_only,
             std::vector<std::string>& keys) {
  for (int level = 0; level < 2 && lua_type(L, -1) == LUA_TTABLE; ++level) {
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
      if (lua_type(L, -2) == LUA_TSTRING) {
        std::string key = lua_tostring(L, -2);
        if (is_name(key) && starts_with(key, partial) && !starts_with(key, "__") &&
            (!functions_only || lua_isfunction(L, -1)))
          keys.push_back(key);
      }
      lua_pop(L, 1);
    }
    // Tables that inherit fields through __index (classes): one level is enough here.
    if (!lua_getmetatable(L, -1)) break;
    lua_pushstring(L, "__index");
    lua_rawget(L, -2);
    lua_remove(L, -2);
    lua_remove(L, -2);
  }
  lua_pop(L, 1);
}

}  // namespace

std::vector<std::string> complete(lua_State* L, const std::string& word) {
  const int top = lua_gettop(L);
  std::vector<std::string> out;
  const std::size_t cut = word.find_last_of(".:");
  if (cut == std::string::npos) {
    lua_pushglobaltable(L);
    collect(L, word, false, out);
    for (const char* k : keywords)
      if (starts_with(k, word)) out.emplace_back(k);
  } else {
    const std::string base = word.substr(0, cut), partial = word.substr(cut + 1);
    const bool method = word[cut] == ':';
    if (base.find(':') != std::string::npos) return out;  // "a:b.c" names nothing
    // Walk a.b.c with raw reads from the globals.
    lua_pushglobaltable(L);
    std::size_t pos = 0;
    bool ok = true;
    while (ok) {
      std::size_t dot = base.find('.', pos);
      std::string key = base.substr(pos, dot == std::string::npos ? std::string::npos : dot - pos);
      push_fields(L);
      if (!is_name(key) || lua_isnil(L, -1)) {
        ok = false;
        break;
      }
      lua_pushstring(L, key.c_str());
      lua_rawget(L, -2);
      lua_remove(L, -2);
      if (lua_isnil(L, -1)) ok = false;
      if (dot == std::string::npos) break;
      pos = dot + 1;
    }
    if (ok) {
      push_fields(L);
      std::vector<std::string> keys;
      collect(L, partial, method, keys);
      for (const auto& k : keys) out.push_back(base + word[cut] + k);
    }
  }
  lua_settop(L, top);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace granule::lua
