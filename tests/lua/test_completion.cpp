// Tab completion reads the live state without running any metamethod.
#include <catch2/catch.hpp>
#include <lua.hpp>

#include "lua/completion.hpp"
#include "lua/scene.hpp"

using namespace granule;

namespace {
bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}
}  // namespace

TEST_CASE("completion: globals, library fields and simulation methods", "[repl]") {
  lua::SceneContext ctx;
  lua_State* L = lua::new_state(&ctx);
  REQUIRE(luaL_dostring(L, "sim = simulation { dimension = 2 } granule = require 'granule'") ==
          LUA_OK);
  auto globals = lua::complete(L, "simul");
  CHECK(globals == std::vector<std::string>{"simulation", "simulations"});
  CHECK(has(lua::complete(L, "wh"), "while"));  // keywords too
  CHECK(lua::complete(L, "sim:ru") == std::vector<std::string>{"sim:run"});
  auto set = lua::complete(L, "sim:set_");
  CHECK(has(set, "sim:set_velocity"));
  CHECK(has(set, "sim:set_wall"));
  CHECK_FALSE(has(set, "sim:run"));
  CHECK(lua::complete(L, "granule.vec.no") == std::vector<std::string>{"granule.vec.norm"});
  CHECK(lua::complete(L, "string.up") == std::vector<std::string>{"string.upper"});
  CHECK(lua::complete(L, "no_such.thing").empty());
  CHECK(lua::complete(L, "sim:run.x").empty());
  CHECK(lua_gettop(L) == 0);  // the stack is left as it was

  // Strict globals and a simulation's "no such method" __index must not fire.
  lua::make_globals_strict(L);
  CHECK(lua::complete(L, "undeclared.x").empty());
  CHECK(lua::complete(L, "sim:zz").empty());
  CHECK(lua_gettop(L) == 0);
  lua_close(L);
}
