// Discipline at the C++/Lua boundary (Debian's Lua is built as C: a Lua error
// is a longjmp that would skip C++ destructors).
//  - Every binding runs its body inside `protect`, which catches C++
//    exceptions and raises the Lua error only after the C++ frames are gone.
//  - Bindings read arguments with the readers below, which throw C++
//    exceptions instead of calling luaL_check* (which would longjmp), and
//    read tables raw (lua_rawget, lua_rawgeti, lua_rawlen), so that no
//    metamethod runs (and raises) inside a protected body.
//  - Lua callbacks are called with lua_pcall and a traceback handler
//    (call_lua), and their errors become C++ exceptions (ScriptError) naming
//    the callback on the way back into the engine.
#pragma once

#include <array>
#include <cstdarg>
#include <cstdint>
#include <lua.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace granule::lua {

// An error raised by Lua code (a callback); its message already carries file:line.
struct ScriptError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The directory of Granule's Lua package: $GRANULE_LUA_PATH, else the
// source tree's lua/ (what scene.cpp puts on package.path).
std::string library_dir();
// Whether a chunk's source ("@path") is a file of that package (granule/ or
// granule.lua under library_dir()).
bool is_library_source(const char* source);

// Pushes "file:line: " of the nearest script line calling into C, or "" if none:
// the first level of the stack that runs Lua code outside Granule's own package
// (a stage that granule.stage ran is the scene's line that called it), else
// the first that runs Lua code at all. Bindings are reached through wrappers
// (the arity check, the journal), which are C levels of their own.
inline void push_script_where(lua_State* L) {
  lua_Debug ar, first;
  bool found = false;
  for (int level = 1; lua_getstack(L, level, &ar); ++level) {
    if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
    if (!found) first = ar, found = true;
    if (!is_library_source(ar.source)) {
      first = ar;
      break;
    }
  }
  if (found)
    lua_pushfstring(L, "%s:%d: ", first.short_src, first.currentline);
  else
    lua_pushliteral(L, "");
}

// luaL_error with push_script_where's position instead of level 1's.
inline int script_error(lua_State* L, const char* format, ...) {
  va_list args;
  va_start(args, format);
  push_script_where(L);
  lua_pushvfstring(L, format, args);
  va_end(args);
  lua_concat(L, 2);
  return lua_error(L);
}

// Runs body(L) -> int; converts any C++ exception into a Lua error prefixed with
// the calling script's file:line (push_script_where).
template <typename Body>
int protect(lua_State* L, Body&& body) {
  int result = 0;
  bool failed = false;
  bool script = false;
  {
    std::string message;
    try {
      result = body(L);
    } catch (const ScriptError& e) {
      message = e.what();
      failed = script = true;
    } catch (const std::exception& e) {
      message = e.what();
      failed = true;
    }
    if (failed) {
      if (!script) push_script_where(L);
      lua_pushstring(L, message.c_str());
      if (!script) lua_concat(L, 2);
    }
  }
  if (failed) return lua_error(L);
  return result;
}

std::string type_name(lua_State* L, int index);
// Whether the value at `index` has a metatable with an __index field (read raw).
bool has_index_metamethod(lua_State* L, int index);

// Reads fields of a Lua table at a stack index; throws std::runtime_error naming
// the context and key. A table for a function of the API table (api_docs.cpp)
// is checked against its documented keys when the reader is made, so an unknown
// key is reported before a missing required one; finish() refuses keys that
// were not read, suggesting the nearest known name.
class TableReader {
 public:
  TableReader(lua_State* L, int index, std::string context);
  bool has(const char* key);
  double number(const char* key);                   // required
  double number(const char* key, double fallback);  // optional
  std::int64_t integer(const char* key);
  std::int64_t integer(const char* key, std::int64_t fallback);
  bool boolean(const char* key, bool fallback);
  std::string string(const char* key);
  std::string string(const char* key, const std::string& fallback);
  std::array<double, 3> vector(const char* key, int dimension);  // {x, y[, z]}
  std::array<double, 3> vector(const char* key, int dimension,
                               const std::array<double, 3>& fallback);
  std::vector<double> numbers(const char* key);
  // Leaves the field on the stack top if it is a function and returns true.
  bool push_function(const char* key);
  bool push_table(const char* key);  // the same for a table
  void finish();
  const std::string& context() const { return context_; }
  int index() const { return index_; }
  void mark(const char* key) { used_.insert(key); }
  std::vector<std::string> keys();  // string keys present

 private:
  [[noreturn]] void refuse_missing(const char* key);
  int push(const char* key);  // pushes field, returns its type
  void refuse_undocumented_keys();
  // The keys the API table declares for this call (empty: it declares none).
  std::vector<std::string> declared_keys() const;
  lua_State* L_;
  int index_;
  std::string context_;
  std::set<std::string> used_;
};

std::array<double, 3> read_vector(lua_State* L, int index, int dimension, const std::string& what);
double read_number(lua_State* L, int index, const std::string& what);
std::string read_string(lua_State* L, int index, const std::string& what);
std::int64_t read_integer(lua_State* L, int index, const std::string& what);
void push_vector(lua_State* L, const std::array<double, 3>& v, int dimension);

// The strings of the list at `index`; throws naming `what`[k] if one is not a string.
std::vector<std::string> read_string_list(lua_State* L, int index, const std::string& what);

}  // namespace granule::lua
