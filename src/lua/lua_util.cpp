#include "lua/lua_util.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "contact/parameters.hpp"
#include "core/errors.hpp"
#include "lua/api_docs.hpp"

namespace granule::lua {

std::string type_name(lua_State* L, int index) {
  return luaL_typename(L, index);
}

std::string library_dir() {
  const char* env = std::getenv("GRANULE_LUA_PATH");
  return env ? env : GRANULE_LUA_DIR;
}

bool is_library_source(const char* source) {
  // As Lua names the package's files from package.path's "DIR/?.lua;DIR/?/init.lua".
  static const std::string prefix = "@" + library_dir() + "/granule";
  if (!source) return false;
  const std::string_view s(source);
  if (s.size() <= prefix.size() || s.compare(0, prefix.size(), prefix) != 0) return false;
  const std::string_view rest = s.substr(prefix.size());
  return rest.front() == '/' || rest == ".lua";
}

namespace {
// What a value that is not an integer is, for "must be an integer, got ...":
// a number is shown (2.5, 1e+19 beyond the 64-bit integers), anything else by type.
std::string not_an_integer(lua_State* L, int index) {
  if (lua_type(L, index) != LUA_TNUMBER) return type_name(L, index);
  const lua_Number v = lua_tonumber(L, index);
  if (v == std::floor(v) && std::isfinite(v))
    return fmt::format("{} (beyond the 64-bit integers)", v);
  return fmt::format("{}", v);
}
}  // namespace

bool has_index_metamethod(lua_State* L, int index) {
  if (!lua_getmetatable(L, index)) return false;
  lua_pushliteral(L, "__index");
  const bool found = lua_rawget(L, -2) != LUA_TNIL;
  lua_pop(L, 2);
  return found;
}

TableReader::TableReader(lua_State* L, int index, std::string context)
    : L_(L), index_(lua_absindex(L, index)), context_(std::move(context)) {
  if (!lua_istable(L, index_))
    throw std::runtime_error(
        fmt::format("{}: expected a table {{ ... }}, got {}", context_, type_name(L, index_)));
  // The reads below are raw, so a proxy's fields (parameters{}'s table, a table with
  // defaults behind __index) would read as absent: say so instead.
  if (has_index_metamethod(L, index_))
    throw std::runtime_error(fmt::format(
        "{}: expected a plain table {{ ... }}, got one with an __index metamethod, whose "
        "fields are not read; copy them into a plain table",
        context_));
  refuse_undocumented_keys();
}

// A binding reads its keys one by one and raises the first error it meets, so a
// misspelt key ('radis') would be reported as the required one it stands for
// ("'radius_min' is required"). The keys a function takes are declared once, in
// the API table (api_docs.cpp): a table checked against them before anything is
// read reports the misspelling first, for every binding the table describes.
// The context names the function: "fill", or "material 'glass'" (a quoted
// name after it); nested tables ("fill.region") and parameter specifications
// ("parameters: 'x'") are checked by finish() as they are read.
std::vector<std::string> TableReader::declared_keys() const {
  const std::size_t end = context_.find(' ');
  if (end != std::string::npos && context_.compare(end, 2, " '") != 0) return {};
  const std::string name = context_.substr(0, end);
  if (name.empty() || name.find_first_of(".:") != std::string::npos) return {};
  const FunctionDoc* doc = find_doc(name);
  if (!doc || doc->form != CallForm::table || doc->open_keys) return {};
  std::vector<std::string> known;
  for (const ArgDoc& a : doc->args) known.emplace_back(a.name);
  return known;
}

void TableReader::refuse_undocumented_keys() {
  const std::vector<std::string> known = declared_keys();
  if (known.empty()) return;
  lua_pushnil(L_);
  while (lua_next(L_, index_) != 0) {
    lua_pop(L_, 1);
    if (lua_type(L_, -1) != LUA_TSTRING) {
      // A positional entry the call declares ("1", "2": a law's materials, a hook's
      // function) is read by its binding; any other would be ignored, silently
      // (sim:set_damping { 0.7 } would switch damping off).
      const bool whole = lua_isinteger(L_, -1);
      const std::string at = whole ? std::to_string(lua_tointeger(L_, -1)) : std::string();
      if (whole && std::find(known.begin(), known.end(), at) != known.end()) continue;
      const std::string shown =
          whole ? "[" + at + "]"
                : std::string("a key of type ") + lua_typename(L_, lua_type(L_, -1));
      lua_pop(L_, 1);
      std::vector<std::string> named;
      for (const auto& k : known)
        if (k.find_first_not_of("0123456789") != std::string::npos) named.push_back(k);
      throw std::runtime_error(
          fmt::format("{}: an entry at {} has no name: give it as name = value ({})", context_,
                      shown, fmt::join(named, ", ")));
    }
    std::string key = lua_tostring(L_, -1);
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    lua_pop(L_, 1);
    std::string hint = nearest_name(key, known);
    throw std::runtime_error(
        fmt::format("{}: unknown key '{}'{}", context_, key,
                    hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
  }
}

// A required key is absent. In a table no declared key list covers (a nested one, as
// fill.region's), a present key that is a near spelling of it is the likelier mistake:
// name that one first. A key the call declares is no misspelling, only not read yet.
void TableReader::refuse_missing(const char* key) {
  const std::vector<std::string> declared = declared_keys();
  std::string typo;
  lua_pushnil(L_);
  while (lua_next(L_, index_) != 0) {
    lua_pop(L_, 1);
    if (lua_type(L_, -1) == LUA_TSTRING && typo.empty()) {
      std::string present = lua_tostring(L_, -1);
      const bool is_declared =
          std::find(declared.begin(), declared.end(), present) != declared.end();
      if (!used_.count(present) && !is_declared && !nearest_name(present, {key}).empty())
        typo = present;
    }
  }
  if (!typo.empty())
    throw std::runtime_error(
        fmt::format("{}: unknown key '{}' (did you mean '{}'?)", context_, typo, key));
  throw std::runtime_error(fmt::format("{}: '{}' is required", context_, key));
}

// Raw reads: a metamethod that raised would longjmp over this reader's destructors.
int TableReader::push(const char* key) {
  used_.insert(key);
  lua_pushstring(L_, key);
  return lua_rawget(L_, index_);
}

bool TableReader::has(const char* key) {
  lua_pushstring(L_, key);
  int t = lua_rawget(L_, index_);
  lua_pop(L_, 1);
  return t != LUA_TNIL;
}

double TableReader::number(const char* key) {
  if (!has(key)) refuse_missing(key);
  return number(key, 0);
}

double TableReader::number(const char* key, double fallback) {
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (t != LUA_TNUMBER) {
    std::string got = type_name(L_, -1);
    lua_pop(L_, 1);
    throw std::runtime_error(fmt::format("{}: '{}' must be a number, got {}", context_, key, got));
  }
  double v = lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  if (!std::isfinite(v))
    throw std::runtime_error(
        fmt::format("{}: '{}' must be finite, got {}", context_, key, number_text(v)));
  return v;
}

std::int64_t TableReader::integer(const char* key) {
  if (!has(key)) refuse_missing(key);
  return integer(key, 0);
}

std::int64_t TableReader::integer(const char* key, std::int64_t fallback) {
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  int ok = 0;
  lua_Integer v = lua_tointegerx(L_, -1, &ok);
  std::string got = not_an_integer(L_, -1);
  lua_pop(L_, 1);
  if (!ok || t != LUA_TNUMBER)
    throw std::runtime_error(
        fmt::format("{}: '{}' must be an integer, got {}", context_, key, got));
  return v;
}

bool TableReader::boolean(const char* key, bool fallback) {
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (t != LUA_TBOOLEAN) {
    std::string got = type_name(L_, -1);
    lua_pop(L_, 1);
    throw std::runtime_error(
        fmt::format("{}: '{}' must be true or false, got {}", context_, key, got));
  }
  bool v = lua_toboolean(L_, -1);
  lua_pop(L_, 1);
  return v;
}

std::string TableReader::string(const char* key) {
  if (!has(key)) refuse_missing(key);
  return string(key, "");
}

std::string TableReader::string(const char* key, const std::string& fallback) {
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  if (t != LUA_TSTRING) {
    std::string got = type_name(L_, -1);
    lua_pop(L_, 1);
    throw std::runtime_error(fmt::format("{}: '{}' must be a string, got {}", context_, key, got));
  }
  std::string v = lua_tostring(L_, -1);
  lua_pop(L_, 1);
  return v;
}

std::array<double, 3> TableReader::vector(const char* key, int dimension) {
  if (!has(key)) refuse_missing(key);
  return vector(key, dimension, {0, 0, 0});
}

std::array<double, 3> TableReader::vector(const char* key, int dimension,
                                          const std::array<double, 3>& fallback) {
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  std::array<double, 3> v;
  try {
    v = read_vector(L_, -1, dimension, fmt::format("{}: '{}'", context_, key));
  } catch (...) {
    lua_pop(L_, 1);
    throw;
  }
  lua_pop(L_, 1);
  return v;
}

std::vector<double> TableReader::numbers(const char* key) {
  std::vector<double> out;
  int t = push(key);
  if (t == LUA_TNIL) {
    lua_pop(L_, 1);
    return out;
  }
  if (t != LUA_TTABLE) {
    lua_pop(L_, 1);
    throw std::runtime_error(fmt::format("{}: '{}' must be a list of numbers", context_, key));
  }
  const auto n = static_cast<lua_Integer>(lua_rawlen(L_, -1));
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L_, -1, k);
    if (lua_type(L_, -1) != LUA_TNUMBER || !std::isfinite(lua_tonumber(L_, -1))) {
      lua_pop(L_, 2);
      throw std::runtime_error(
          fmt::format("{}: '{}'[{}] must be a finite number", context_, key, k));
    }
    out.push_back(lua_tonumber(L_, -1));
    lua_pop(L_, 1);
  }
  lua_pop(L_, 1);
  return out;
}

bool TableReader::push_function(const char* key) {
  int t = push(key);
  if (t == LUA_TFUNCTION) return true;
  std::string got = type_name(L_, -1);
  lua_pop(L_, 1);
  if (t == LUA_TNIL) return false;
  throw std::runtime_error(fmt::format("{}: '{}' must be a function, got {}", context_, key, got));
}

bool TableReader::push_table(const char* key) {
  int t = push(key);
  if (t == LUA_TTABLE) return true;
  std::string got = type_name(L_, -1);
  lua_pop(L_, 1);
  if (t == LUA_TNIL) return false;
  throw std::runtime_error(fmt::format("{}: '{}' must be a table, got {}", context_, key, got));
}

std::vector<std::string> TableReader::keys() {
  std::vector<std::string> out;
  lua_pushnil(L_);
  while (lua_next(L_, index_) != 0) {
    if (lua_type(L_, -2) == LUA_TSTRING) out.emplace_back(lua_tostring(L_, -2));
    lua_pop(L_, 1);
  }
  return out;
}

void TableReader::finish() {
  std::vector<std::string> known(used_.begin(), used_.end());
  lua_pushnil(L_);
  while (lua_next(L_, index_) != 0) {
    lua_pop(L_, 1);
    if (lua_type(L_, -1) != LUA_TSTRING) continue;  // positional entries are read by callers
    std::string key = lua_tostring(L_, -1);
    if (used_.count(key)) continue;
    lua_pop(L_, 1);
    std::string hint = nearest_name(key, known);
    throw std::runtime_error(
        fmt::format("{}: unknown key '{}'{}", context_, key,
                    hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
  }
}

std::array<double, 3> read_vector(lua_State* L, int index, int dimension, const std::string& what) {
  index = lua_absindex(L, index);
  if (!lua_istable(L, index))
    throw std::runtime_error(fmt::format("{} must be a vector {{x, y{}}}, got {}", what,
                                         dimension == 3 ? ", z" : "", type_name(L, index)));
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
  if (n != dimension && !(dimension == 2 && n == 3))
    throw std::runtime_error(fmt::format("{} must have {} components, got {}", what, dimension,
                                         static_cast<long long>(n)));
  std::array<double, 3> v{0, 0, 0};
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, index, k);
    if (lua_type(L, -1) != LUA_TNUMBER) {
      std::string got = type_name(L, -1);
      lua_pop(L, 1);
      throw std::runtime_error(fmt::format("{}[{}] must be a number, got {}", what, k, got));
    }
    v[k - 1] = lua_tonumber(L, -1);
    lua_pop(L, 1);
    if (!std::isfinite(v[k - 1]))
      throw std::runtime_error(fmt::format("{}[{}] must be finite", what, k));
  }
  if (dimension == 2 && v[2] != 0)
    throw std::runtime_error(fmt::format("{}: a 2D scene has no z component (got {})", what, v[2]));
  return v;
}

double read_number(lua_State* L, int index, const std::string& what) {
  if (lua_type(L, index) != LUA_TNUMBER)
    throw std::runtime_error(fmt::format("{} must be a number, got {}", what, type_name(L, index)));
  double v = lua_tonumber(L, index);
  if (!std::isfinite(v))
    throw std::runtime_error(fmt::format("{} must be finite, got {}", what, number_text(v)));
  return v;
}

std::int64_t read_integer(lua_State* L, int index, const std::string& what) {
  int ok = 0;
  lua_Integer v = lua_tointegerx(L, index, &ok);
  if (!ok || lua_type(L, index) != LUA_TNUMBER)
    throw std::runtime_error(
        fmt::format("{} must be an integer, got {}", what, not_an_integer(L, index)));
  return v;
}

std::string read_string(lua_State* L, int index, const std::string& what) {
  if (lua_type(L, index) != LUA_TSTRING)
    throw std::runtime_error(fmt::format("{} must be a string, got {}", what, type_name(L, index)));
  return lua_tostring(L, index);
}

void push_vector(lua_State* L, const std::array<double, 3>& v, int dimension) {
  lua_createtable(L, dimension, 0);
  for (int k = 0; k < dimension; ++k) {
    lua_pushnumber(L, v[k]);
    lua_rawseti(L, -2, k + 1);
  }
}

// A Lua list of strings (raw reads), each entry named in the error.
std::vector<std::string> read_string_list(lua_State* L, int index, const std::string& what) {
  if (!lua_istable(L, index)) throw std::runtime_error(what + " must be a list of names");
  std::vector<std::string> out;
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, index));
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, index, k);
    if (lua_type(L, -1) != LUA_TSTRING) {
      lua_pop(L, 1);
      throw std::runtime_error(fmt::format("{}[{}] must be a string", what, k));
    }
    out.emplace_back(lua_tostring(L, -1));
    lua_pop(L, 1);
  }
  return out;
}

}  // namespace granule::lua
