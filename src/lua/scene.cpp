#include "lua/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "contact/parameters.hpp"
#include "core/names.hpp"
#include "io/case_record.hpp"
#include "lua/api_docs.hpp"
#include "lua/journal.hpp"
#include "lua/lua_util.hpp"
#include "lua/ordered_pairs.hpp"

namespace granule::lua {

namespace {
const char* context_key = "granule.context";
volatile std::sig_atomic_t interrupt_flag = 0;
volatile std::sig_atomic_t interrupt_signal_number = SIGINT;

int traceback(lua_State* L) {
  const char* msg = lua_tostring(L, 1);
  // A callback's error (call_lua) carries the traceback from where it was raised, which
  // already runs down to the main chunk.
  if (msg && std::strstr(msg, "\nstack traceback:")) return 1;
  if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
  luaL_traceback(L, L, msg, 1);
  return 1;
}

// require "granule.names" -> { nearest_name = f }: nearest_name(name, { candidates })
// returns the candidate core/names.hpp's nearest_name picks, or nil, so that the Lua
// library (lua/granule/checks.lua) suggests names exactly as the C++ errors do.
int l_nearest_name(lua_State* L) {
  return protect(L, [](lua_State* L) {
    const std::string name = read_string(L, 1, "nearest_name: name");
    if (!lua_istable(L, 2))
      throw std::runtime_error(
          fmt::format("nearest_name: the candidates must be a list of "
                      "strings, got {}",
                      type_name(L, 2)));
    std::vector<std::string> candidates;
    const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, 2));
    for (lua_Integer k = 1; k <= n; ++k) {
      if (lua_rawgeti(L, 2, k) != LUA_TSTRING) {
        const std::string got = type_name(L, -1);
        lua_pop(L, 1);
        throw std::runtime_error(
            fmt::format("nearest_name: candidate {} must be a string, got {}", k, got));
      }
      std::size_t length = 0;
      const char* text = lua_tolstring(L, -1, &length);
      candidates.emplace_back(text, length);
      lua_pop(L, 1);
    }
    const std::string best = nearest_name(name, candidates);
    if (best.empty())
      lua_pushnil(L);
    else
      lua_pushlstring(L, best.data(), best.size());
    return 1;
  });
}

int open_names_module(lua_State* L) {
  lua_newtable(L);
  lua_pushcfunction(L, l_nearest_name);
  lua_setfield(L, -2, "nearest_name");
  return 1;
}

// What parameters { name = { min =, max =, above =, below =, integer = } } allows.
struct ParameterRange {
  bool integer = false;
  std::optional<double> min, max, above, below;
  void read(TableReader& r) {
    if (r.has("min")) min = r.number("min");
    if (r.has("max")) max = r.number("max");
    if (r.has("above")) above = r.number("above");
    if (r.has("below")) below = r.number("below");
    integer = r.boolean("integer", false);
  }
  bool any() const { return integer || min || max || above || below; }
  bool in_bounds(double v) const {
    return (!integer || v == std::floor(v)) && (!min || v >= *min) && (!max || v <= *max) &&
           (!above || v > *above) && (!below || v < *below);
  }
  // A whole number must also fit a Lua integer (what the scene reads it as).
  bool fits(double v) const { return !integer || std::abs(v) < 9.2e18; }
  bool holds(double v) const { return in_bounds(v) && fits(v); }
  // "a whole number >= 1 and <= 100000", "> 0"
  std::string text() const {
    std::vector<std::string> parts;
    if (min) parts.push_back(fmt::format(">= {}", *min));
    if (above) parts.push_back(fmt::format("> {}", *above));
    if (max) parts.push_back(fmt::format("<= {}", *max));
    if (below) parts.push_back(fmt::format("< {}", *below));
    std::string out = integer ? "a whole number" : "";
    for (std::size_t k = 0; k < parts.size(); ++k)
      out += (k == 0 ? (integer ? " " : "") : " and ") + parts[k];
    return out;
  }
};

// parameters { name = default, other = { default = 1.0, unit = "m/s", doc = "..." } }
// Returns a read-only table of values; -D name=value overrides a default.
int l_parameters(lua_State* L) {
  return protect(L, [](lua_State* L) {
    SceneContext* ctx = context(L);
    if (ctx->parameters_declared)
      throw std::runtime_error("parameters{...} may be called only once per scene");
    ctx->parameters_declared = true;
    if (!lua_istable(L, 1) || has_index_metamethod(L, 1))
      throw std::runtime_error("parameters: expected a plain table { name = default, ... }");
    lua_newtable(L);  // values
    int values = lua_gettop(L);
    std::vector<std::string> names;
    lua_pushnil(L);
    while (lua_next(L, 1) != 0) {
      if (lua_type(L, -2) != LUA_TSTRING)
        throw std::runtime_error("parameters: every key must be a name");
      std::string name = lua_tostring(L, -2);
      names.push_back(name);
      int spec = lua_gettop(L);
      ParameterDoc described{name, "", "", ""};
      // { min =, max =, above =, below =, integer = }: the values a -D may give (a count
      // of 1e300 would run for ever, a negative radius make nonsense).
      ParameterRange range;
      if (lua_istable(L, spec)) {
        // { default =, unit =, doc = }: a misspelt key would silently drop its value.
        TableReader r(L, spec, fmt::format("parameters: '{}'", name));
        described.unit = r.string("unit", "");
        described.doc = r.string("doc", "");
        range.read(r);
        r.mark("default");
        r.finish();
        lua_pushliteral(L, "default");
        lua_rawget(L, spec);
        lua_replace(L, spec);
      }
      int t = lua_type(L, spec);
      if (t != LUA_TNUMBER && t != LUA_TSTRING && t != LUA_TBOOLEAN)
        throw std::runtime_error(fmt::format(
            "parameters: '{}' needs a default that is a number, string or boolean, got {}", name,
            luaL_typename(L, spec)));
      if (t == LUA_TNUMBER && !std::isfinite(lua_tonumber(L, spec)))
        throw std::runtime_error(
            fmt::format("parameters: '{}' has a default that is not finite", name));
      if (range.any() && t != LUA_TNUMBER)
        throw std::runtime_error(fmt::format(
            "parameters: '{}' has a range (min, max, above, below, integer) but a default that "
            "is not a number",
            name));
      if (range.any() && !range.holds(lua_tonumber(L, spec)))
        throw std::runtime_error(fmt::format("parameters: '{}' has a default {} that is not {}",
                                             name, lua_tonumber(L, spec), range.text()));
      if (range.any())
        described.doc += (described.doc.empty() ? "" : " ") + ("(" + range.text() + ")");
      described.default_value = t == LUA_TBOOLEAN  ? (lua_toboolean(L, spec) ? "true" : "false")
                                : t == LUA_TNUMBER ? fmt::format("{}", lua_tonumber(L, spec))
                                                   : lua_tostring(L, spec);
      ctx->parameter_docs.push_back(described);  // granule run SCENE --help
      const bool default_is_integer = t == LUA_TNUMBER && lua_isinteger(L, spec);
      auto ov = ctx->overrides.find(name);
      if (ov != ctx->overrides.end()) {
        ctx->consumed.insert(name);
        const std::string& text = ov->second;
        if (t == LUA_TNUMBER) {
          if (!lua_stringtonumber(L, text.c_str()))
            throw std::runtime_error(
                fmt::format("-D {}={}: '{}' expects a number", name, text, name));
          if (!std::isfinite(lua_tonumber(L, -1)))
            throw std::runtime_error(fmt::format("-D {}={}: must be finite", name, text));
          if (!range.in_bounds(lua_tonumber(L, -1)))
            throw std::runtime_error(
                fmt::format("-D {}={}: '{}' must be {}", name, text, name, range.text()));
          if (!range.fits(lua_tonumber(L, -1)))
            throw std::runtime_error(fmt::format(
                "-D {}={}: '{}' is a whole number, and this one is beyond the 64-bit integers "
                "(|{}| < 9.2e18)",
                name, text, name, name));
          // A whole number written as a float (exponent, decimal point) from 2^53 on
          // has lost digits already: 9.007199254740993e15 reads as ...992.
          if (range.integer && !lua_isinteger(L, -1) &&
              std::abs(lua_tonumber(L, -1)) >= 9007199254740992.0)
            throw std::runtime_error(fmt::format(
                "-D {}={}: '{}' is a whole number from 2^53 on written as a float, which holds it "
                "only to about 16 digits: write it in full (digits only)",
                name, text, name));
          // A value written as not zero that reads as zero (1e-400) is a slip, not a zero.
          if (lua_tonumber(L, -1) == 0 && text.find_first_of("123456789") != std::string::npos &&
              text.find_first_of("eE") != std::string::npos)
            throw std::runtime_error(fmt::format(
                "-D {}={}: below the smallest number a double holds (it would read as 0)", name,
                text));
        } else if (t == LUA_TBOOLEAN) {
          if (text != "true" && text != "false")
            throw std::runtime_error(
                fmt::format("-D {}={}: '{}' expects true or false", name, text, name));
          lua_pushboolean(L, text == "true");
        } else {
          lua_pushstring(L, text.c_str());
        }
        lua_replace(L, spec);
      }
      // A number's Lua type follows the declaration, not how -D wrote it: a whole
      // number (integer = true) is an integer ("run_" .. n gives run_10, not
      // run_10.0, for -D n=1e1), and a parameter with a fractional default a float.
      if (t == LUA_TNUMBER && !(range.integer && lua_isinteger(L, spec))) {
        const lua_Number value = lua_tonumber(L, spec);
        if (range.integer && range.fits(value))
          lua_pushinteger(L, static_cast<lua_Integer>(value)), lua_replace(L, spec);
        else if (!range.integer && !default_is_integer)
          lua_pushnumber(L, value), lua_replace(L, spec);
      }
      // record for provenance
      std::string shown;
      if (lua_type(L, spec) == LUA_TNUMBER) {
        ctx->numeric_parameters[name] = lua_tonumber(L, spec);
        // Declared whole (integer = true): an integer in the output, whatever -D wrote.
        if (range.integer && lua_isinteger(L, spec))
          ctx->integer_parameters[name] = lua_tointeger(L, spec);
        shown = fmt::format("{}", lua_tonumber(L, spec));
      } else if (lua_type(L, spec) == LUA_TBOOLEAN) {
        shown = lua_toboolean(L, spec) ? "true" : "false";
      } else {
        shown = lua_tostring(L, spec);
      }
      ctx->parameter_values.emplace_back(name, shown);
      lua_pushvalue(L, -2);
      lua_pushvalue(L, spec);
      lua_rawset(L, values);
      lua_settop(L, values + 1);  // keep key for lua_next
    }
    for (const auto& [name, value] : ctx->overrides) {
      if (ctx->consumed.count(name)) continue;
      std::string hint = nearest_name(name, names);
      throw std::runtime_error(
          fmt::format("-D {}={}: this scene has no parameter '{}'{}", name, value, name,
                      hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint)));
    }
    if (ctx->parameters_only) {
      ctx->declared_parameters = names;
      ctx->stopped_after_parameters = true;
      throw std::runtime_error(parameters_checked_stop);
    }
    // Read-only proxy that refuses unknown names.
    lua_newtable(L);
    lua_newtable(L);
    lua_pushvalue(L, values);
    lua_pushcclosure(
        L,
        [](lua_State* L) -> int {
          lua_pushvalue(L, 2);
          if (lua_rawget(L, lua_upvalueindex(1)) == LUA_TNIL)
            return luaL_error(L, "unknown parameter '%s'", luaL_tolstring(L, 2, nullptr));
          return 1;
        },
        1);
    lua_setfield(L, -2, "__index");
    lua_pushcfunction(L, [](lua_State* L) -> int {
      return luaL_error(L, "parameters are read-only: override them with -D name=value");
    });
    lua_setfield(L, -2, "__newindex");
    lua_pushvalue(L, values);
    lua_pushcclosure(
        L,
        [](lua_State* L) -> int {  // __pairs so scripts can list them
          lua_getglobal(L, "next");
          lua_pushvalue(L, lua_upvalueindex(1));
          lua_pushnil(L);
          return 3;
        },
        1);
    lua_setfield(L, -2, "__pairs");
    lua_setmetatable(L, -2);
    return 1;
  });
}

int strict_index(lua_State* L) {
  const char* name = lua_tostring(L, 2);
  {
    // The nearest global there is (`simulaton` -> `simulation`).
    std::vector<std::string> globals;
    lua_pushnil(L);
    while (lua_next(L, 1) != 0) {
      lua_pop(L, 1);
      if (lua_type(L, -1) == LUA_TSTRING) globals.emplace_back(lua_tostring(L, -1));
    }
    const std::string hint = name ? nearest_name(name, globals) : std::string();
    luaL_where(L, 1);
    lua_pushstring(
        L, fmt::format("undeclared global '{}'{} (a typo? locals need 'local')", name ? name : "?",
                       hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint))
               .c_str());
    lua_concat(L, 2);
  }  // (lua_error does not return: nothing with a destructor may be alive there)
  return lua_error(L);
}
int strict_newindex(lua_State* L) {
  const char* name = lua_tostring(L, 2);
  return luaL_error(L, "assignment to undeclared global '%s': declare it with 'local'",
                    name ? name : "?");
}
}  // namespace

namespace {
volatile std::sig_atomic_t run_active_flag = 0;
}
void set_run_active(bool active) {
  run_active_flag = active ? 1 : 0;
}
bool run_active() {
  return run_active_flag != 0;
}

void request_interrupt(int signal_number) {
  interrupt_signal_number = signal_number;
  interrupt_flag = 1;
}
bool interrupt_pending() {
  return interrupt_flag != 0;
}
void clear_interrupt() {
  interrupt_flag = 0;
}
int interrupt_signal() {
  return interrupt_signal_number;
}
const char* interrupt_cause() {
  switch (interrupt_signal_number) {
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "Ctrl-C";
  }
}

SceneContext* context(lua_State* L) {
  lua_getfield(L, LUA_REGISTRYINDEX, context_key);
  auto* ctx = static_cast<SceneContext*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  return ctx;
}

namespace {

// package.searchers[2] with Lua's own as upvalue 1: a module's file, once found, is
// read and its digest noted for the checkpoints (the text is what `require` loads).
int noting_searcher(lua_State* L) {
  const int given = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, given, LUA_MULTRET);
  SceneContext* ctx = context(L);
  if (ctx && lua_gettop(L) >= 2 && lua_isfunction(L, 1) && lua_type(L, 2) == LUA_TSTRING) {
    // Absolute: a restart run from another folder finds the same file.
    const std::string path = std::filesystem::absolute(lua_tostring(L, 2)).string();
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    auto& noted = ctx->module_sources;
    if (std::none_of(noted.begin(), noted.end(), [&](const auto& m) { return m.first == path; }))
      noted.emplace_back(path, io::source_digest(text.str()));
  }
  return lua_gettop(L);
}

}  // namespace

lua_State* new_state(SceneContext* ctx) {
  lua_State* L = luaL_newstate();
  if (!L) throw std::runtime_error("cannot create a Lua state (out of memory)");
  luaL_openlibs(L);
  open_ordered_pairs(L);
  // os.exit(code) would end the program with the scene's simulations open, and
  // their files would lose what is still buffered (the last rows of a series):
  // it closes the Lua state, and so the simulations and their files, first, as
  // os.exit(code, true) does.
  lua_getglobal(L, "os");
  lua_getfield(L, -1, "exit");
  lua_pushcclosure(
      L,
      [](lua_State* S) -> int {
        lua_settop(S, 1);
        lua_pushboolean(S, 1);
        lua_pushvalue(S, lua_upvalueindex(1));
        lua_insert(S, 1);
        lua_call(S, 2, 0);  // does not return
        return 0;
      },
      1);
  lua_setfield(L, -2, "exit");
  lua_pop(L, 1);
  lua_pushlightuserdata(L, ctx);
  lua_setfield(L, LUA_REGISTRYINDEX, context_key);
  // lua/ of the source tree (or $GRANULE_LUA_PATH) on package.path.
  const std::string dir = library_dir();
  lua_getglobal(L, "package");
  lua_getfield(L, -1, "path");
  std::string path = fmt::format("{0}/?.lua;{0}/?/init.lua;{1}", dir, lua_tostring(L, -1));
  lua_pop(L, 1);
  lua_pushstring(L, path.c_str());
  lua_setfield(L, -2, "path");
  // C modules only from absolute directories: Lua's default cpath ends with
  // ./?.so, so a `require` run in a directory holding a stray .so of that name
  // would load and run native code the user never meant to (docs/security.md).
  lua_getfield(L, -1, "cpath");
  const std::string given = lua_tostring(L, -1);
  lua_pop(L, 1);
  std::string cpath;
  for (std::size_t from = 0; from <= given.size();) {
    std::size_t to = given.find(';', from);
    if (to == std::string::npos) to = given.size();
    const std::string entry = given.substr(from, to - from);
    if (!entry.empty() && entry[0] == '/') cpath += (cpath.empty() ? "" : ";") + entry;
    from = to + 1;
  }
  lua_pushstring(L, cpath.c_str());
  lua_setfield(L, -2, "cpath");
  // Lua's searcher of Lua files, wrapped to note each file it finds (module_sources).
  lua_getfield(L, -1, "searchers");
  lua_rawgeti(L, -1, 2);
  lua_pushcclosure(L, noting_searcher, 1);
  lua_rawseti(L, -2, 2);
  lua_pop(L, 1);
  // The C++ half of the Lua library (lua/granule/checks.lua).
  lua_getfield(L, -1, "preload");
  lua_pushcfunction(L, open_names_module);
  lua_setfield(L, -2, "granule.names");
  lua_pop(L, 2);
  push_checked(L, *find_doc("parameters"), l_parameters);
  lua_setglobal(L, "parameters");
  lua_pushstring(L, GRANULE_VERSION);
  lua_setglobal(L, "GRANULE_VERSION");
  lua_pushstring(L, ctx->scene_path.c_str());
  lua_setglobal(L, "SCENE_PATH");
  // wall_time(): seconds of wall-clock time from an arbitrary origin, for timing
  // runs (os.clock counts CPU time of every thread, so it overstates parallel runs).
  push_checked(L, *find_doc("wall_time"), [](lua_State* L) -> int {
    lua_pushnumber(
        L,
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
    return 1;
  });
  lua_setglobal(L, "wall_time");
  open_simulation(L);
  open_help(L);
  journal_clocks(L);
  return L;
}

void make_globals_strict(lua_State* L) {
  lua_pushglobaltable(L);
  lua_newtable(L);
  lua_pushcfunction(L, strict_index);
  lua_setfield(L, -2, "__index");
  lua_pushcfunction(L, strict_newindex);
  lua_setfield(L, -2, "__newindex");
  lua_setmetatable(L, -2);
  lua_pop(L, 1);
}

std::string run_file(lua_State* L, const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return fmt::format("'{}' is a directory, not a scene file", path);
  std::ifstream in(path, std::ios::binary);
  if (!in) return fmt::format("cannot open scene file '{}'", path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string source = buffer.str();
  if (SceneContext* ctx = context(L); ctx && ctx->scene_source.empty()) ctx->scene_source = source;
  // "@path": Lua's messages then carry the file and line.
  std::string err = run_string(L, source, "@" + path);
  if (err.empty()) {
    SceneContext* ctx = context(L);
    if (ctx && !ctx->parameters_declared && !ctx->overrides.empty())
      err = fmt::format("{}: -D {} given, but the scene declares no parameters{{...}}", path,
                        ctx->overrides.begin()->first);
    // A scene that ends before its journal does never reached the checkpoint's point:
    // the checkpoint is another scene's, and nothing was continued.
    if (err.empty() && ctx && !ctx->restart_path.empty() && !ctx->parameters_only &&
        !restart_applied(*ctx))
      err = fmt::format(
          "restart: the scene ended before it reached the point where {} was written (the "
          "checkpoint's journal holds calls this scene did not make); nothing was continued",
          ctx->restart_path);
  }
  return err;
}

std::string run_string(lua_State* L, const std::string& chunk, const std::string& chunk_name) {
  lua_pushcfunction(L, traceback);
  int handler = lua_gettop(L);
  if (luaL_loadbuffer(L, chunk.data(), chunk.size(), chunk_name.c_str()) != LUA_OK) {
    std::string err = lua_tostring(L, -1);
    lua_settop(L, handler - 1);
    return err;
  }
  std::string err;
  if (lua_pcall(L, 0, 0, handler) != LUA_OK)
    err = lua_tostring(L, -1) ? lua_tostring(L, -1) : "error";
  lua_settop(L, handler - 1);
  return err;
}

}  // namespace granule::lua
