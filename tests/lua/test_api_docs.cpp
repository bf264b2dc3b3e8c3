// The documentation table is the API's one description: everything a scene
// can call has an entry, every entry names something that exists, and the
// arity it states is enforced.
#include <catch2/catch.hpp>
#include <lua.hpp>
#include <set>
#include <string>

#include "lua/api_docs.hpp"
#include "lua/scene.hpp"

using namespace granule;

namespace {

struct State {
  lua::SceneContext ctx;
  lua_State* L;
  State() : L(lua::new_state(&ctx)) {}
  ~State() { lua_close(L); }
  // Runs a chunk; returns "" or its error.
  std::string run(const std::string& code) {
    std::string err;
    if (luaL_dostring(L, code.c_str()) != LUA_OK) {
      err = lua_tostring(L, -1) ? lua_tostring(L, -1) : "?";
      lua_pop(L, 1);
    }
    lua_settop(L, 0);
    return err;
  }
};

std::set<std::string> string_keys(lua_State* L, int index) {
  std::set<std::string> keys;
  index = lua_absindex(L, index);
  lua_pushnil(L);
  while (lua_next(L, index) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) keys.insert(lua_tostring(L, -2));
    lua_pop(L, 1);
  }
  return keys;
}

// Names of the functions in the table on the stack top, recursively ("vec.add").
void library_functions(lua_State* L, const std::string& prefix, std::set<std::string>& out) {
  lua_pushnil(L);
  while (lua_next(L, -2) != 0) {
    if (lua_type(L, -2) == LUA_TSTRING) {
      std::string name = prefix + lua_tostring(L, -2);
      if (lua_isfunction(L, -1)) out.insert(name);
      if (lua_istable(L, -1)) library_functions(L, name + ".", out);
      if (lua_type(L, -1) == LUA_TNUMBER) out.insert(name);  // documented values (granule.pi)
    }
    lua_pop(L, 1);
  }
}

std::set<std::string> documented(const char* section) {
  std::set<std::string> names;
  for (const auto& d : lua::api_docs())
    if (std::string(d.section) == section) names.insert(d.name);
  return names;
}

}  // namespace

TEST_CASE("api docs: every simulation method has an entry and every entry a method", "[docs]") {
  State s;
  luaL_getmetatable(s.L, "granule.Simulation");
  lua_getfield(s.L, -1, "__index");
  std::set<std::string> methods;
  for (const auto& k : string_keys(s.L, -1)) methods.insert("sim:" + k);
  lua_settop(s.L, 0);
  REQUIRE(methods.size() > 30);
  CHECK(methods == documented("simulation"));
}

TEST_CASE("api docs: every global Granule adds has an entry and every entry a global", "[docs]") {
  State s;
  lua_State* plain = luaL_newstate();
  luaL_openlibs(plain);
  lua_pushglobaltable(plain);
  std::set<std::string> standard = string_keys(plain, -1);
  lua_pushglobaltable(s.L);
  std::set<std::string> added;
  for (const auto& k : string_keys(s.L, -1)) {
    // A standard function Granule replaced (pairs) counts as added: it behaves otherwise.
    lua_getfield(plain, -1, k.c_str());
    lua_getfield(s.L, -1, k.c_str());
    const bool replaced =
        lua_iscfunction(plain, -1) && lua_tocfunction(plain, -1) != lua_tocfunction(s.L, -1);
    lua_pop(plain, 1);
    lua_pop(s.L, 1);
    if (!standard.count(k) || replaced) added.insert(k);
  }
  lua_close(plain);
  lua_settop(s.L, 0);
  CHECK(added.count("pairs") == 1);
  CHECK(added == documented("global"));
}

TEST_CASE("api docs: every function of the granule library has an entry and vice versa", "[docs]") {
  State s;
  REQUIRE(s.run("package.loaded.granule_for_test = require 'granule'") == "");
  lua_getglobal(s.L, "require");
  lua_pushstring(s.L, "granule");
  lua_call(s.L, 1, 1);
  std::set<std::string> found;
  library_functions(s.L, "granule.", found);
  lua_settop(s.L, 0);
  REQUIRE(found.size() > 10);
  CHECK(found == documented("library"));
}

TEST_CASE("api docs: each entry is complete", "[docs]") {
  std::set<std::string> names;
  for (const auto& d : lua::api_docs()) {
    INFO(d.name);
    CHECK(names.insert(d.name).second);  // no duplicates
    CHECK(std::string(d.doc).size() > 3);
    CHECK(std::string(d.signature).find(std::string(d.name).substr(4)) != std::string::npos);
    if (d.form != lua::CallForm::value && d.args.empty() && d.form == lua::CallForm::table)
      FAIL("a table-form function documents no keys");
    for (const auto& a : d.args) {
      static const std::set<std::string> types = {
          "number", "integer", "string", "boolean", "vector", "table", "function", "list", "any"};
      INFO(a.name);
      CHECK(types.count(a.type));
      CHECK(std::string(a.doc).size() > 0);
    }
  }
}

TEST_CASE("api docs: short names, help and the arity check", "[docs]") {
  REQUIRE(lua::find_doc("fill") != nullptr);
  CHECK(std::string(lua::find_doc("fill")->name) == "sim:fill");
  CHECK(std::string(lua::find_doc("sim.run")->name) == "sim:run");
  CHECK(std::string(lua::find_doc("vec.add")->name) == "granule.vec.add");
  CHECK(lua::find_doc("no_such_thing") == nullptr);
  CHECK(lua::nearest_doc_name("fil") == "fill");
  CHECK_THAT(lua::format_help(*lua::find_doc("sim:run")), Catch::Contains("duration"));
  CHECK_THAT(lua::api_markdown(), Catch::Contains("### `sim:picture`"));

  State s;
  CHECK(s.run("help('sim:run')") == "");
  CHECK(s.run("help(simulation)") == "");
  CHECK_THAT(s.run("help('fil')"), Catch::Contains("did you mean 'fill'"));
  CHECK(s.run("local sim = simulation { dimension = 2 } help(sim.run) help(sim)") == "");
  CHECK_THAT(s.run("local sim = simulation { dimension = 2 } sim:time(1)"),
             Catch::Contains("sim:time expects 0 arguments, got 1"));
  CHECK_THAT(s.run("local sim = simulation { dimension = 2 } sim.time()"),
             Catch::Contains("call it with a colon"));
  CHECK_THAT(s.run("local sim = simulation { dimension = 2 } sim:run({ steps = 1 }, 2)"),
             Catch::Contains("sim:run expects one table"));
  CHECK_THAT(s.run("local sim = simulation { dimension = 2 } sim:runn { steps = 1 }"),
             Catch::Contains("did you mean 'run'"));
  CHECK_THAT(s.run("simulation({}, 1)"), Catch::Contains("simulation expects one table"));
}

// The library's argument check names what was wrong, down to a vector's component.
TEST_CASE("api docs: a refused library argument is named, a vector's bad component too", "[docs]") {
  State s;
  CHECK_THAT(
      s.run("local g = require 'granule' g.vec.add({ 1, 0 / 0 }, { 1, 2 })"),
      Catch::Contains("argument 1 (a) must be a vector") && Catch::Contains("component 2 = nan"));
  CHECK_THAT(s.run("local g = require 'granule' g.vec.dot({ 1, 2 }, { 1, nil, 3 })"),
             Catch::Contains("argument 2 (b)") && Catch::Contains("component 2 = nil"));
  CHECK_THAT(s.run("local g = require 'granule' g.vec.norm({ 1 })"),
             Catch::Contains("a table of 1 component"));
  CHECK_THAT(s.run("local g = require 'granule' g.particle_row({ 0, 0 }, { 1, 0 }, 3, -1e-3)"),
             Catch::Contains("radius must be > 0"));
  CHECK(
      s.run("local g = require 'granule' assert(g.particle_row({ 0, 0 }, { 1, 0 }, 3, 1e-3)[3][1] "
            "== 4e-3)") == "");
}
