// Scenes that must be refused, each with a message naming the file, the line
// and the parameter; and scenes that must run.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <lua.hpp>

#include "core/names.hpp"
#include "lua/scene.hpp"

using namespace granule;

namespace {
struct SceneRun {
  std::string error;
  std::string path;
};

// Writes `source` to a scene file, runs it with strict globals, returns the error ("" = ok).
SceneRun run_scene(const std::string& source, std::map<std::string, std::string> overrides = {}) {
  static int counter = 0;
  auto dir = std::filesystem::temp_directory_path() / "granule_lua_tests";
  std::filesystem::create_directories(dir);
  SceneRun r;
  // Unique per process: ctest runs test cases in parallel processes.
  const std::string tag = std::to_string(getpid()) + "_" + std::to_string(++counter);
  r.path = (dir / ("scene_" + tag + ".lua")).string();
  std::ofstream(r.path) << source;
  lua::SceneContext ctx;
  ctx.scene_path = r.path;
  ctx.overrides = std::move(overrides);
  ctx.output_path = (dir / ("out_" + tag + ".h5")).string();
  ctx.quiet = true;
  lua_State* L = lua::new_state(&ctx);
  lua::make_globals_strict(L);
  r.error = lua::run_file(L, r.path);
  lua_close(L);
  std::filesystem::remove(r.path);
  std::filesystem::remove(ctx.output_path);
  return r;
}

const char* header = R"(local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "glass", "glass", model = "walton_braun", k_load = 1e4, restitution = 0.9, friction = 0.3 }
sim:contact { "glass", "steel", model = "walton_braun", k_load = 1e4, restitution = 0.9, friction = 0.5 }
)";  // five lines

void expect_refused(const std::string& body, int line, const std::string& needle) {
  auto r = run_scene(std::string(header) + body);
  INFO("scene body: " << body << "\nerror: " << r.error);
  REQUIRE_FALSE(r.error.empty());
  CHECK_THAT(r.error, Catch::Contains(std::filesystem::path(r.path).filename().string() + ":" +
                                      std::to_string(line) + ":"));
  CHECK_THAT(r.error, Catch::Contains(needle));
}
}  // namespace

TEST_CASE("lua: a valid scene runs", "[lua]") {
  auto r = run_scene(std::string(header) + R"(
sim:wall_cylinder { name = "drum", center = {0, 0}, radius = 0.01, material = "steel", angular_velocity = 10 }
sim:fill { region = { circle = { center = {0, 0}, radius = 0.01 } }, count = 50, radius = 5e-4, material = "glass", max_speed = 0.01 }
local n = 0
sim:every { steps = 10, function(s) n = n + 1 end }
local res = sim:run { steps = 100 }
assert(res.steps == 100 and n == 10, "callbacks fired " .. n .. " times")
assert(#sim:particles() == 50)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: bad physical input is refused with the parameter named", "[lua][errors]") {
  expect_refused("sim:add_particle { position = {0, 0}, radius = -1e-3, material = 'glass' }\n", 6,
                 "radius must be > 0");
  expect_refused("sim:material { name = 'x', density = -5 }\n", 6, "'density' must be >= 0");
  expect_refused(
      "sim:contact { 'steel', 'steel', model = 'walton_braun', k_load = 1e4, restitution = 1.5 }\n",
      6, "'restitution' = 1.5");
  expect_refused(
      "sim:contact { 'steel', 'steel', model = 'walton_braun', k_load = 1e4, restitution = 0 }\n",
      6, "'restitution' = 0");
  expect_refused(
      "sim:contact { 'steel', 'steel', model = 'linear', k_normal = 1e4, restitution = 0.5, "
      "friction = -0.1 }\n",
      6, "'friction' = -0.1");
  expect_refused("sim:add_particle { position = {0, 0}, radius = 1e-3, material = 'glas' }\n", 6,
                 "unknown material 'glas' (did you mean 'glass'?)");
  expect_refused(
      "sim:contact { 'steel', 'steel', model = 'walton_braun', k_lod = 1e4, restitution = 0.5 }\n",
      6, "unknown parameter 'k_lod' (did you mean 'k_load'?)");
  expect_refused(
      "sim:contact { 'steel', 'steel', model = 'waltonbraun', k_load = 1, restitution = 0.5 }\n", 6,
      "unknown contact model 'waltonbraun'");
  expect_refused("sim:contact { 'steel', 'steel', model = 'walton_braun', restitution = 0.5 }\n", 6,
                 "'k_load' [N/m] is required");
  expect_refused(
      "sim:add_particle { position = {0, 0}, radius = 1e-3, material = 'glass', velocity = {0/0, "
      "0} }\n",
      6, "must be finite");
  expect_refused(
      "sim:wall_cylinder { name = 'c', center = {0, 0}, radius = 0.01, velocity = {1, 0}, "
      "material = 'steel' }\n",
      6, "a circle does not translate; a closed polyline of arcs");
  expect_refused("sim:set_contact('glass', 'glass', { model = 'linear' })\n", 6,
                 "a pair's model is set once, by sim:contact");
  // 0/0 is a NaN with its sign bit set: shown as "nan", not "-nan".
  expect_refused("sim:material { name = 'x', density = 0/0 }\n", 6,
                 "'density' must be finite, got nan");
  expect_refused(
      "sim:add_particle { position = {0, 0}, radius = 1e-3, material = 'glass', colour = 'red' }\n",
      6, "unknown key 'colour'");
}

TEST_CASE("lua: a particle outside the walls is refused when the run starts", "[lua][errors]") {
  expect_refused(
      R"(sim:wall_cylinder { name = "drum", center = {0, 0}, radius = 0.01, material = "steel" }
sim:add_particle { position = {0.02, 0}, radius = 1e-3, material = "glass" }
sim:run { steps = 1 }
)",
      8, "lies outside wall 'drum'");
}

TEST_CASE("lua: a hard wall contact going on across runs is no particle outside the wall",
          "[lua][errors]") {
  // A soft disk pressed past the floor by its speed: after 15 ms its centre is
  // half a radius below the floor (overlap 1.5 r), a contact the run goes on
  // with; the next run, which lists afresh for a particle added, must go on
  // with it too.
  auto r = run_scene(std::string(header) + R"(
sim:material { name = "jelly", density = 1000 }
sim:contact { "jelly", "steel", model = "linear", k_normal = 1e-3, restitution = 1 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:set { time_step = 1e-4 }
local id = sim:add_particle { position = { 0, 1e-3 }, radius = 1e-3, material = "jelly", velocity = { 0, -0.1 } }
sim:run { duration = 0.015 }
local y = sim:particle(id).position[2]
assert(y < 0 and y > -1e-3, "centre past the floor by less than a radius: " .. y)
sim:add_particle { position = { 0.01, 2e-3 }, radius = 1e-3, material = "steel", fixed = true }
sim:run { steps = 10 }
)");
  CHECK(r.error == "");
  // Added during a scene with its centre past a wall: refused at once.
  expect_refused(
      R"(sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:add_particle { position = { 0, 2e-3 }, radius = 1e-3, material = "glass" }
sim:run { steps = 1 }
sim:add_particle { position = { 0, -0.5e-3 }, radius = 1e-3, material = "glass" }
)",
      9, "particle at (0, -0.0005) would lie outside wall 'floor'");
  // A wall added during a scene across a particle's centre: refused at once.
  expect_refused(R"(sim:add_particle { position = { 0, 2e-3 }, radius = 1e-3, material = "glass" }
sim:run { steps = 1 }
sim:wall_plane { name = "floor", point = { 0, 2.5e-3 }, normal = { 0, 1 }, material = "steel" }
)",
                 8, "wall 'floor': particle 0 at (0, 0.002");
}

TEST_CASE("lua: a pair without a contact law is named", "[lua][errors]") {
  expect_refused(R"(sim:material { name = "rubber", density = 1000 }
sim:add_particle { position = {0, 0}, radius = 1e-3, material = "rubber" }
sim:add_particle { position = {3e-3, 0}, radius = 1e-3, material = "glass" }
sim:run { steps = 1 }
)",
                 9, "no contact law for materials 'glass' and 'rubber'");
}

TEST_CASE("lua: a material's only particle needs no law with itself, until a second one joins",
          "[lua][errors]") {
  // A sphere dropped on a wall: the run needs the sphere-wall law only.
  const std::string lone = R"(sim:material { name = "rubber", density = 1000 }
sim:contact { "rubber", "steel", model = "linear", k_normal = 1e4, restitution = 0.5 }
sim:wall_plane { name = "floor", point = {0, 0}, normal = {0, 1}, material = "steel" }
local id = sim:add_particle { position = {0, 2e-3}, radius = 1e-3, material = "rubber" }
sim:gravity { 0, -9.81 }
local r = sim:run { duration = 0.05 }
assert(r.steps > 0)
local y = sim:particle(id).position[2]
assert(y > 0.5e-3 and y < 1.5e-3, "the sphere rests on the floor: y = " .. y)
)";
  auto r = run_scene(std::string(header) + lone);
  CHECK(r.error == "");
  // A second rubber sphere: now rubber-rubber contacts can occur.
  expect_refused(
      lone + R"(sim:add_particle { position = {5e-3, 2e-3}, radius = 1e-3, material = "rubber" }
sim:run { steps = 1 }
)",
      16, "no contact law for materials 'rubber' and 'rubber'");
}

TEST_CASE("lua: a disk that goes through a thin wall within a step stops the run",
          "[lua][errors]") {
  // Fired at 0.9 of its radius a step, the disk's centre can pass the wall's
  // surface between two steps that both lie short of the depth test's 0.9 r:
  // a thin wall (a polyline, a bounded segment) then pushed it on out of the
  // far side, silently.
  const std::string fire =
      R"(local id = sim:add_particle { position = {0, 0}, radius = 5e-4, material = "glass" }
local v = 0.9 * 5e-4 / sim:time_step()
sim:set_velocity(id, { v * math.cos(0.35), v * math.sin(0.35) })
sim:run { duration = 2e-2 / v }
)";
  expect_refused(
      R"(sim:wall_polyline { name = "box", material = "steel", closed = true, points = { {-5e-3, -5e-3}, {5e-3, -5e-3}, {5e-3, 5e-3}, {-5e-3, 5e-3} } }
)" + fire,
      10, "went through wall 'box'");
  expect_refused(
      R"(sim:wall_plane { name = "east", material = "steel", point = {5e-3, 0}, normal = {-1, 0}, size = 1e-2 }
)" + fire,
      10, "went through wall 'east'");
}

TEST_CASE("lua: a time step above the stability limit is refused, above the rule warned",
          "[lua][errors]") {
  auto r = run_scene(R"(local sim = simulation { dimension = 2, time_step = 1e-3 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.9 }
sim:add_particle { position = {0, 0}, radius = 1e-3, material = "glass" }
sim:run { steps = 1 }
)");
  CHECK_THAT(r.error, Catch::Contains(":5:"));
  CHECK_THAT(r.error, Catch::Contains("above the stability limit"));
}

TEST_CASE("lua: accidental globals and unknown methods are errors", "[lua][errors]") {
  expect_refused("velocity = 3\n", 6, "assignment to undeclared global 'velocity'");
  expect_refused("local x = undefined_thing + 1\n", 6, "undeclared global 'undefined_thing'");
  expect_refused("sim:add_partcle { }\n", 6, "no method 'add_partcle'");
}

TEST_CASE("lua: callback errors carry the callback's line", "[lua][errors]") {
  expect_refused(R"(sim:add_particle { position = {0, 0}, radius = 1e-3, material = "glass" }
sim:every { steps = 1, function(s)
  error("boom")
end }
sim:run { steps = 5 }
)",
                 8, "boom");
}

TEST_CASE("lua: an error in a call that Granule's own package makes names the scene's line",
          "[lua][errors]") {
  // granule.stage (lua/granule/init.lua) runs sim:run, which refuses the value:
  // the message points at the scene's call, not at the package's line.
  const std::string body = R"(local granule = require "granule"
sim:add_particle { position = {0, 0}, radius = 1e-3, material = "glass" }
granule.stage(sim, { name = "bad", steps = 5, check_every = -1 })
)";
  expect_refused(body, 8, "check_every");
  const auto r = run_scene(std::string(header) + body);
  const std::string first_line = r.error.substr(0, r.error.find('\n'));
  CHECK_THAT(first_line, Catch::StartsWith(r.path + ":8:"));
  CHECK_THAT(first_line, !Catch::Contains("init.lua"));
}

TEST_CASE("lua: -D overrides declared parameters and refuses unknown ones", "[lua][parameters]") {
  const std::string scene =
      R"(local p = parameters { speed = { default = 1.0, unit = "m/s" }, label = "a", flag = false }
assert(p.speed == 2.5, "speed " .. p.speed)
assert(p.label == "b")
assert(p.flag == true)
)";
  CHECK(run_scene(scene, {{"speed", "2.5"}, {"label", "b"}, {"flag", "true"}}).error == "");
  auto bad = run_scene(scene, {{"sped", "2.5"}});
  CHECK_THAT(bad.error, Catch::Contains("no parameter 'sped' (did you mean 'speed'?)"));
  auto wrong_type = run_scene(scene, {{"speed", "fast"}});
  CHECK_THAT(wrong_type.error, Catch::Contains("expects a number"));
  auto read_unknown = run_scene("local p = parameters { a = 1 }\nlocal x = p.b\n");
  CHECK_THAT(read_unknown.error, Catch::Contains(":2:"));
  CHECK_THAT(read_unknown.error, Catch::Contains("unknown parameter 'b'"));
}

TEST_CASE("lua: a parameter's number type follows its declaration, not the -D text",
          "[lua][parameters]") {
  // A whole number is an integer however -D writes it; a fractional default's
  // parameter is a float; an integer default without a range keeps what -D gives.
  const std::string scene =
      R"(local p = parameters { n = { default = 10, integer = true }, x = 1.5, k = 3 }
assert(math.type(p.n) == "integer" and "run_" .. p.n == "run_" .. N, "n: " .. tostring(p.n))
assert(math.type(p.x) == "float" and p.x == X, "x: " .. tostring(p.x))
assert(math.type(p.k) == K, "k: " .. tostring(p.k))
)";
  auto expecting = [&](const char* values) {
    return std::string("local N, X, K = ") + values + "\n" + scene;
  };
  CHECK(
      run_scene(expecting("12, 2.0, 'integer'"), {{"n", "1.2e1"}, {"x", "2"}, {"k", "4"}}).error ==
      "");
  CHECK(run_scene(expecting("12, 1.5, 'float'"), {{"n", "12.0"}, {"k", "2.5"}}).error == "");
  CHECK(run_scene(expecting("10, 1.5, 'integer'")).error == "");
  // A whole number past what a Lua integer holds is refused, not read as a float.
  for (const char* big : {"1e19", "9223372036854775808"}) {
    INFO("-D n=" << big);
    CHECK_THAT(
        run_scene(expecting("0, 1.5, 'integer'"), {{"n", big}}).error,
        Catch::Contains("'n' is a whole number, and this one is beyond the 64-bit integers"));
  }
  // From 2^53 on a float may have lost digits (...993e15 reads as 2^53): refused;
  // written in full it is exact.
  for (const char* big : {"9.007199254740993e15", "9.007199254740992e15", "-1e16"}) {
    INFO("-D n=" << big);
    CHECK_THAT(run_scene(expecting("0, 1.5, 'integer'"), {{"n", big}}).error,
               Catch::Contains("'n' is a whole number from 2^53 on written as a float"));
  }
  CHECK(
      run_scene(expecting("9007199254740993, 1.5, 'integer'"), {{"n", "9007199254740993"}}).error ==
      "");
  CHECK(run_scene(expecting("9007199254740991, 1.5, 'integer'"), {{"n", "9.007199254740991e15"}})
            .error == "");
}

TEST_CASE("lua: a value that must be an integer is shown when it is not one", "[lua][errors]") {
  expect_refused(
      "sim:fill { region = { circle = { center = {0, 0}, radius = 0.01 } }, count = 2.5, "
      "radius = 1e-3, material = 'glass' }\n",
      6, "'count' must be an integer, got 2.5");
  expect_refused(
      "sim:fill { region = { circle = { center = {0, 0}, radius = 0.01 } }, count = 1e19, "
      "radius = 1e-3, material = 'glass' }\n",
      6, "'count' must be an integer, got 1e+19 (beyond the 64-bit integers)");
  expect_refused("sim:run { steps = 10.5 }\n", 6, "must be an integer, got 10.5");
}

TEST_CASE("lua: a second contact law for a pair names both declarations", "[lua][errors]") {
  // The header declares glass-steel on line 5; again here, in the other order, on line 6.
  auto r = run_scene(std::string(header) +
                     "sim:contact { 'steel', 'glass', model = 'linear', k_normal = 1e4, "
                     "restitution = 0.5 }\n");
  const std::string file = std::filesystem::path(r.path).filename().string();
  INFO("error: " << r.error);
  CHECK_THAT(r.error, Catch::Contains("declared twice"));
  CHECK_THAT(r.error, Catch::Contains("first at "));
  CHECK_THAT(r.error, Catch::Contains(file + ":5, again at "));
  CHECK_THAT(r.error, Catch::Contains(file + ":6"));
  CHECK_THAT(r.error, Catch::Contains("sim:set_contact"));
  // A deliberate change goes through set_contact.
  CHECK(run_scene(std::string(header) + "sim:set_contact('steel', 'glass', { friction = 0.2 })\n")
            .error == "");
}

TEST_CASE("lua: an entry without a name is refused where the call takes none", "[lua][errors]") {
  // It would be ignored: set_damping { 0.7 } would switch damping off, silently.
  expect_refused("sim:set_damping { 0.7 }\n", 6,
                 "set_damping: an entry at [1] has no name: give it as name = value (viscous, "
                 "spin, local_fraction)");
  expect_refused("sim:output { 5, snapshot_every = 1e-3 }\n", 6,
                 "output: an entry at [1] has no name");
  expect_refused("sim:set_damping { [true] = 1 }\n", 6, "an entry at a key of type boolean");
  // Entries a call declares by position still read: a law's materials, a hook's function.
  CHECK(run_scene(std::string(header) + "sim:every { steps = 10, function(s) end }\n").error == "");
}

TEST_CASE("lua: an unknown key is reported before a missing required one", "[lua][errors]") {
  // 'radis' stands for 'radius', whose absence the binding would otherwise report
  // as "'radius_min' is required".
  expect_refused(
      "sim:fill { region = { circle = { center = {0, 0}, radius = 0.008 } }, count = 5, radis = "
      "3e-4, material = 'glass' }\n",
      6, "fill: unknown key 'radis' (did you mean 'radius'?)");
  expect_refused("sim:add_particle { position = {0, 0}, radiu = 1e-3, material = 'glass' }\n", 6,
                 "unknown key 'radiu' (did you mean 'radius'?)");
  expect_refused(
      "sim:wall_plane { nam = 'floor', point = {0, 0}, normal = {0, 1}, material = "
      "'steel' }\n",
      6, "unknown key 'nam' (did you mean 'name'?)");
  expect_refused("sim:material { nme = 'x', density = 1 }\n", 6, "unknown key 'nme'");
  auto r = run_scene("local sim = simulation { dimensio = 2 }\n");
  CHECK_THAT(r.error,
             Catch::Contains("simulation: unknown key 'dimensio' (did you mean 'dimension'?)"));
}

TEST_CASE("lua: requests that cannot be met are refused with the reason", "[lua][errors]") {
  // Poisson's ratio must lie in (-1, 0.5]: at -1 the shear modulus is infinite.
  expect_refused("sim:material { name = 'x', density = 1, young = 1e9, poisson = -1 }\n", 6,
                 "'poisson' must be in (-1, 0.5]");
  CHECK(run_scene(std::string(header) +
                  "sim:material { name = 'x', density = 1, young = 1e9, poisson = 0.5 }\n")
            .error == "");
  // A skin wider than the whole scene.
  expect_refused(R"(sim:add_particle { position = {0, 0}, radius = 1e-3, material = "glass" }
sim:add_particle { position = {3e-3, 0}, radius = 1e-3, material = "glass" }
sim:set { skin = 1 }
sim:run { steps = 1 }
)",
                 9, "skin 1 m is larger than the scene (0.005 m across its particles and walls)");
  // More particles than the machine's memory holds: refused at once, with the estimate.
  expect_refused(
      "sim:fill { region = { circle = { center = {0, 0}, radius = 0.008 } }, count = 900000000, "
      "radius = 1e-6, material = 'glass' }\n",
      6, "GB of memory available");
}

TEST_CASE("lua: a scene loads no C module from the current directory", "[lua]") {
  // A stray module in the working directory: Lua's default cpath (./?.so) would find it.
  const std::string name = "granule_stray_module_" + std::to_string(getpid());
  std::ofstream(name + ".so") << "not a library";
  auto r = run_scene("assert(package.searchpath('" + name +
                     "', package.cpath) == nil, 'found ' .. tostring(package.searchpath('" + name +
                     "', package.cpath)))\nfor entry in package.cpath:gmatch('[^;]+') do "
                     "assert(entry:sub(1, 1) == '/', entry) end\n");
  std::filesystem::remove(name + ".so");
  CHECK(r.error == "");
}

// ---- the Lua/C++ boundary ----

// A table whose every metamethod raises: a binding that read it through lua_getfield or
// luaL_len would longjmp out of its C++ body (skipping destructors: ASan sees the leak).
const char* raising_table =
    "local raising = setmetatable({}, { __index = function() error('index ran') end,\n"
    "  __len = function() error('len ran') end })\n";  // two lines

TEST_CASE("lua: a table whose __index raises is refused by name, and no metamethod runs",
          "[lua][errors][boundary]") {
  const std::string pre = raising_table;  // after the header: lines 6 and 7
  // A keyword table: refused as a proxy, before any key is read.
  expect_refused(pre + "sim:fill(raising)\n", 8, "fill: expected a plain table");
  expect_refused(pre + "sim:run(raising)\n", 8, "run: expected a plain table");
  expect_refused(pre + "sim:diagnostic('overlaps', raising)\n", 8, "must be a plain table");
  expect_refused(pre + "sim:contact(raising)\n", 8, "contact: expected a plain table");
  // A vector and a list are read raw: their length is the raw one, so __len never runs.
  expect_refused(pre + "sim:gravity(raising)\n", 8, "gravity must have 2 components, got 0");
  expect_refused(pre + "sim:output {}\nsim:series('s', { 'a' })\nsim:append('s', raising)\n", 10,
                 "append");
  // Fields present and a raising __index for the absent ones: reads through lua_getfield
  // would have filled the reader's set of used keys before the longjmp (a leak that
  // LeakSanitizer reports).
  expect_refused(
      "local t = setmetatable({ count = 5, radius = 1e-3, material = 'glass' },\n"
      "  { __index = function() error('index ran') end })\nsim:fill(t)\n",
      8, "fill: expected a plain table");
  // The scene's own parameters{} proxy raises from __index for unknown names.
  expect_refused("local p = parameters { count = 3 }\nsim:set(p)\n", 7,
                 "set: expected a plain table");
  for (const char* body : {"sim:fill(raising)\n", "sim:gravity(raising)\n"}) {
    auto r = run_scene(std::string(header) + pre + body);
    INFO(r.error);
    CHECK_THAT(r.error, !Catch::Contains("index ran") && !Catch::Contains("len ran"));
  }
}

TEST_CASE("lua: a failing callback names itself and carries its traceback",
          "[lua][errors][boundary]") {
  auto r = run_scene(std::string(header) +
                     R"(sim:add_particle { position = {0, 0}, radius = 1e-3, material = "glass" }
local function inner() local x = nil; return x.y end
sim:every { name = "spin-up", steps = 2, function(s)
  inner()
end }
sim:run { steps = 5 }
)");
  const std::string file = std::filesystem::path(r.path).filename().string();
  INFO("error: " << r.error);
  CHECK_THAT(r.error, Catch::Contains("sim:every callback 'spin-up' (hook "));
  CHECK_THAT(r.error, Catch::Contains(file + ":7: attempt to index a nil value"));
  // The traceback is the callback's: the helper, the callback's line, then the run's.
  CHECK_THAT(r.error, Catch::Contains("stack traceback:"));
  CHECK_THAT(r.error, Catch::Contains(file + ":7: in "));
  CHECK_THAT(r.error, Catch::Contains(file + ":9: in function"));
  CHECK_THAT(r.error, Catch::Contains(file + ":11: in main chunk"));
  // One traceback, not the callback's and then the scene's again.
  const auto first = r.error.find("stack traceback:");
  CHECK(r.error.find("stack traceback:", first + 1) == std::string::npos);

  auto stop =
      run_scene(std::string(header) +
                "sim:add_particle { position = {0, 0}, radius = 1e-3, material = 'glass' }\n"
                "sim:run { steps = 5, check_every = 1, stop_when = function(s) "
                "error('no criterion') end }\n");
  INFO("error: " << stop.error);
  CHECK_THAT(stop.error, Catch::Contains("the run's stop_when: "));
  CHECK_THAT(stop.error, Catch::Contains(":7: no criterion"));
  CHECK_THAT(stop.error, Catch::Contains("stack traceback:"));
}

TEST_CASE("lua: every kind of binding suggests the nearest key", "[lua][errors]") {
  // The API table's keys (sim:run), a nested table (fill.region), a contact model's
  // parameters (set_contact), a diagnostic's options and a parameter's specification.
  expect_refused("sim:run { step = 3 }\n", 6, "run: unknown key 'step' (did you mean 'steps'?)");
  expect_refused(
      "sim:fill { region = { circel = { center = {0, 0}, radius = 0.01 } }, count = 5, "
      "radius = 1e-3, material = 'glass' }\n",
      6, "fill.region: unknown key 'circel' (did you mean 'circle'?)");
  expect_refused(
      "sim:fill { region = { sphere = { center = {0, 0}, radius = 0.01 } }, count = 5, "
      "radius = 1e-3, material = 'glass' }\n",
      6, "fill.region: give one of circle, box");
  // A typo inside the shape's table names the shape the scene wrote.
  expect_refused(
      "sim:fill { region = { circle = { centre = {0, 0}, radius = 0.01 } }, count = 5, "
      "radius = 1e-3, material = 'glass' }\n",
      6, "fill.region.circle: unknown key 'centre' (did you mean 'center'?)");
  expect_refused("sim:set_contact('glass', 'steel', { frction = 0.2 })\n", 6,
                 "unknown parameter 'frction' (did you mean 'friction'?)");
  // A misspelt rolling parameter chooses the model without rolling resistance; the
  // hint still knows the rolling variant's names.
  expect_refused(
      "sim:material { name = 'rubber', density = 1200 }\n"
      "sim:contact { 'rubber', 'rubber', model = 'linear', k_normal = 1e3, rolling_frction = 0.1 "
      "}\n",
      7, "unknown parameter 'rolling_frction' (did you mean 'rolling_friction'?)");
  // Two periodic axes, as a list: one axis is all there is, said so.
  expect_refused(
      "local s3 = simulation { dimension = 3, periodic = { { axis = 'x', origin = 0, length = 1 }, "
      "{ axis = 'y', origin = 0, length = 1 } } }\n",
      6, "simulation.periodic: one periodic axis only");
  expect_refused("sim:diagnostic('overlaps', { windw = 0.1 })\n", 6,
                 "unknown option 'windw' (did you mean 'window'?)");
  expect_refused("local p = parameters { n = { defalt = 3 } }\n", 6,
                 "unknown key 'defalt' (did you mean 'default'?)");
}

TEST_CASE("names: one nearest name for C++ and Lua, case-insensitive", "[lua][names]") {
  // Case-sensitively "YOUNG_X" is 2 edits from "YOUNG" and "young" 5.
  CHECK(nearest_name("YOUNG", {"YOUNG_X", "young"}) == "young");
  CHECK(nearest_name("al2o3", {"PMMA", "Al2O3"}) == "Al2O3");
  CHECK(nearest_name("unobtainium", {"PMMA", "Al2O3"}).empty());
  // Of names equally near and keeping as much of the typed name's ends, the
  // first in byte order, whatever order they come in (a Lua table's changes
  // from run to run); a name that keeps no letter in place is no hint.
  CHECK(nearest_name("zb", {"zc", "ab"}) == "ab");
  CHECK(nearest_name("zb", {"ab", "zc"}) == "ab");
  CHECK(nearest_name("radus", {"radix", "radii"}) == "radii");
  CHECK(nearest_name("radus", {"radii", "radix"}) == "radii");
  CHECK(nearest_name("zz", {"a", "n", "s", "b"}).empty());
  // Equally near, the one keeping more of the typed name's start and end.
  CHECK(nearest_name("radis", {"radii", "radius"}) == "radius");
  CHECK(nearest_name("radis", {"radius", "radii"}) == "radius");
  // Only names within the distance allowed (max(3, length / 3)) are hints.
  CHECK(nearest_name("cylinder", {"linear"}).empty());
  // Two neighbouring letters swapped are one edit: "rmp" is nearer "rpm" than "gap".
  CHECK(edit_distance("rmp", "rpm") == 1);
  CHECK(edit_distance("ab", "ba") == 1);
  CHECK(edit_distance("abc", "ca") == 3);
  CHECK(edit_distance("kitten", "sitting") == 3);
  CHECK(nearest_name("rmp", {"gap", "rpm"}) == "rpm");
  CHECK(nearest_name("rmp", {"rpm", "gap"}) == "rpm");
  // The Lua library's suggestion is the C++ one, for names near and far.
  const std::vector<std::string> candidates = {
      "density_kg_m3", "young_modulus_pa", "poisson_ratio", "PMMA", "glass", "Al2O3"};
  std::string lua_list = "{";
  for (const auto& c : candidates) lua_list += "'" + c + "', ";
  lua_list += "}";
  for (const char* name : {"PMAA", "al2o3", "youngs_modulus_pa", "densty", "glas", "xyz", "poisson",
                           "GLASS", "modulus", "Al", "youngs_mod_pa"}) {
    const std::string expected = nearest_name(name, candidates);
    const std::string scene =
        "local checks = require 'granule.checks'\n"
        "local got = checks.nearest('" +
        std::string(name) + "', " + lua_list +
        ")\n"
        "assert(got == " +
        (expected.empty() ? std::string("nil") : "'" + expected + "'") +
        ", 'got ' .. tostring(got))\n";
    INFO(name << " -> '" << expected << "'");
    CHECK(run_scene(scene).error == "");
  }
  expect_refused("local names = require 'granule.names'\nnames.nearest_name('a', { 'b', 3 })\n", 7,
                 "nearest_name: candidate 2 must be a string, got number");
}

TEST_CASE("lua: sim:remove_hook lets the callback go from the registry", "[lua]") {
  // A script that adds and removes callbacks in a loop must not keep them all:
  // the registry holds as many functions after 200 add/remove rounds as before.
  auto r = run_scene(std::string(header) + R"(
local function registry_functions()
  local n = 0
  for _, v in pairs(debug.getregistry()) do if type(v) == "function" then n = n + 1 end end
  return n
end
local before = registry_functions()
for k = 1, 200 do
  local id = sim:every { steps = 5, function(s) end }
  sim:remove_hook(id)
end
collectgarbage()
local after = registry_functions()
assert(after == before, "registry functions " .. before .. " -> " .. after)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: a hook that removes itself or another leaves every other hook firing", "[lua]") {
  // Three hooks every step; the first removes itself at step 2, and at step 4 the
  // second removes the third and adds a fourth. Every hook fires exactly when it is
  // there: none is skipped after a removal, none fires twice.
  auto r = run_scene(std::string(header) + R"(
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "glass" }
local count = { a = 0, b = 0, c = 0, d = 0 }
local ids = {}
ids.a = sim:every { steps = 1, function(s)
  count.a = count.a + 1
  if s:step_count() == 2 then s:remove_hook(ids.a) end
end }
ids.b = sim:every { steps = 1, function(s)
  count.b = count.b + 1
  if s:step_count() == 4 then
    s:remove_hook(ids.c)
    ids.d = s:every { steps = 1, function() count.d = count.d + 1 end }
  end
end }
ids.c = sim:every { steps = 1, function() count.c = count.c + 1 end }
sim:run { steps = 6 }
-- steps 1..6: a fires at 1, 2; b at all six; c at 1..3 (removed at 4 before it fires);
-- d from step 4 (added at step 4 by b, after b: due the same step) to 6
assert(count.a == 2, "a fired " .. count.a)
assert(count.b == 6, "b fired " .. count.b)
assert(count.c == 3, "c fired " .. count.c)
assert(count.d == 3, "d fired " .. count.d)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: time hooks and the clock keep to the steps a fixed time step divides", "[lua]") {
  // dt = 1e-5 s and hooks every 1e-4 s and 1e-3 s over 1e5 steps: every firing on a
  // multiple of 10 (100) steps, the last at the last step, and the clock at 1 s to the
  // last place. A clock summed step by step drifts ~1e-7 dt and fires ~40 % of them a
  // step late, the last not at all; two runs of half the time end at the same time.
  auto r = run_scene(std::string(header) + R"(
sim:set { time_step = 1e-5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "glass" }
local fired, late, fired_ms, late_ms = 0, 0, 0, 0
sim:every { time = 1e-4, function(s)
  fired = fired + 1
  if s:step_count() % 10 ~= 0 then late = late + 1 end
end }
sim:every { time = 1e-3, function(s)
  fired_ms = fired_ms + 1
  if s:step_count() % 100 ~= 0 then late_ms = late_ms + 1 end
end }
sim:run { duration = 0.5 }
sim:run { duration = 1 - sim:time() }
assert(sim:step_count() == 100000, "steps " .. sim:step_count())
assert(sim:time() == 1.0, string.format("t = %.17g", sim:time()))
assert(fired == 10000 and late == 0, "every 1e-4 s: " .. fired .. " firings, " .. late .. " off their step")
assert(fired_ms == 1000 and late_ms == 0, "every 1e-3 s: " .. fired_ms .. " firings, " .. late_ms .. " off")
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: set_central_strength needs a field, and a schedule outlives its removal", "[lua]") {
  // Without a field the call would change nothing: refused. A field removed while a
  // schedule of its strength runs: the schedule has nothing to set, and the run goes on.
  auto r = run_scene(std::string(header) + R"(
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "glass" }
local ok, err = pcall(sim.set_central_strength, sim, 2)
assert(not ok and tostring(err):find("no central field"), tostring(err))
sim:central_field { point = { 0, 0.01 }, strength = 1 }
sim:schedule { "central_strength", linear = { 0, 1, 1, 2 } }
sim:run { steps = 10 }
sim:remove_central_field()
sim:run { steps = 10 }
assert(sim:central_strength() == 0)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: a scheduled target is not set by hand until its schedule ends", "[lua]") {
  const std::string walls =
      R"(sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:wall_plane { name = "lid", point = { 0, 0.01 }, normal = { 0, -1 }, material = "steel" }
sim:add_particle { position = { 0, 0.001 }, radius = 1e-3, material = "glass" }
local lid = sim:schedule { "wall_velocity", wall = "lid", direction = { 0, -1 }, linear = { 0, 0, 0.1, 0.01 } }
local mu = sim:schedule { "friction", from = "glass", to = "glass", linear = { 0, 0.2, 1, 0.3 } }
)";  // lines 6-10
  // The schedule would set its value again before the next step: refused, naming it.
  expect_refused(
      walls + "sim:set_wall('lid', { velocity = { 0, 0.5 } })\n", 11,
      "set_wall 'lid': its velocity is set by schedule 1 ('wall_velocity') until t = 0.1 s");
  expect_refused(walls + "sim:set_contact('glass', 'glass', { friction = 0.1 })\n", 11,
                 "sim:remove_schedule(2)");
  expect_refused(
      walls + "sim:set_contact('steel', 'glass', { friction = 0.1 })\nsim:remove_schedule(7)\n", 12,
      "remove_schedule: no schedule 7");
  expect_refused(walls +
                     "sim:every { steps = 1, function(s) s:remove_schedule(lid) end }\n"
                     "sim:run { steps = 2 }\n",
                 11, "not from inside a run's callback");
  // Ended, the target keeps its value and takes what is set by hand.
  auto r = run_scene(std::string(header) + walls + R"(
sim:run { duration = 0.02 }
local held = sim:wall("lid").velocity[2]
sim:remove_schedule(lid)
sim:remove_schedule(mu)
assert(math.abs(held + 0.002) < 1e-6, "the ramp's value at 0.02 s: " .. held)
sim:run { duration = 0.01 }
assert(sim:wall("lid").velocity[2] == held, "an ended schedule's wall keeps its velocity")
sim:set_wall("lid", { velocity = { 0, 0.5 } })
sim:set_contact("glass", "glass", { friction = 0.1 })
sim:run { duration = 0.01 }
assert(sim:wall("lid").velocity[2] == 0.5, "set by hand after the schedule ended")
-- Past its last point a schedule sets nothing again: setting its target is not refused.
local floor = sim:schedule { "wall_velocity", wall = "floor", direction = { 0, 1 }, linear = { 0, 0, 0.04, 0.01 } }
sim:run { duration = 0.01 }
assert(sim:time() > 0.04 and sim:wall("floor").velocity[2] == 0.01, "the floor's ramp is over")
sim:set_wall("floor", { velocity = { 0, 0 } })
sim:run { duration = 0.01 }
assert(sim:wall("floor").velocity[2] == 0, "a value set after the ramp's last point stays")
-- A run as long as the ramp ends at its last point give or take the clock's
-- round-off: setting the target then is taken, and stays.
local t = sim:time()
sim:schedule { "friction", from = "glass", to = "steel", linear = { t, 0.5, t + 3e-3, 0.4 } }
sim:run { duration = 3e-3 }
sim:set_contact("glass", "steel", { friction = 0.1 })
sim:run { steps = 3 }
assert(sim:contact_parameters("glass", "steel").friction == 0.1, "the hand's friction after a ramp of the run's length")
-- The central field's strength is claimed alike.
sim:central_field { point = { 0, 0 }, strength = 0 }
local t2 = sim:time()
sim:schedule { "central_strength", linear = { t2, 0, t2 + 1, 5 } }
local ok, message = pcall(sim.set_central_strength, sim, 3)
assert(not ok and message:find("set_central_strength: the field's strength is set by schedule", 1, true), message)
ok, message = pcall(sim.central_field, sim, { point = { 0, 0 }, strength = 50 })
assert(not ok and message:find("central_field: the field's strength is set by schedule", 1, true), message)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: a run of a duration reaches it when a schedule shrinks the time step", "[lua]") {
  // Walton-Braun's unloading stiffness is K_load / e^2: lowering e shortens the
  // automatic step (Eq. 4.1) on the way, so the run needs more steps than it planned.
  auto r = run_scene(std::string(header) + R"(
sim:add_particle { position = { -1.5e-3, 0 }, radius = 1e-3, material = "glass", velocity = { 0.5, 0 } }
sim:add_particle { position = { 1.5e-3, 0 }, radius = 1e-3, material = "glass", velocity = { -0.5, 0 } }
sim:schedule { "restitution", from = "glass", to = "glass", linear = { 0, 0.9, 5e-4, 0.05 } }
local dt0 = sim:time_step()
local run = sim:run { duration = 3e-3 }
assert(sim:time_step() < dt0 / 10, "the step shrank: " .. dt0 .. " -> " .. sim:time_step())
assert(run.time >= 3e-3 and run.time < 3e-3 + sim:time_step(),
       string.format("ended at t = %.17g s after %d steps", run.time, run.steps))
assert(run.steps > math.ceil(3e-3 / dt0), "more steps than planned at the first step")
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: sim:set { time_step = 0 } chooses the automatic step afresh", "[lua]") {
  // An automatic step is only ever shortened on its own: removing the small
  // particle that set it keeps it; time_step = 0 lengthens it again.
  auto r = run_scene(std::string(header) + R"(
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "glass" }
local big = sim:time_step()
local small = sim:add_particle { position = { 5e-3, 0 }, radius = 1e-4, material = "glass" }
local short = sim:time_step()
assert(short < big / 10, "a small particle shortens the step: " .. big .. " -> " .. short)
sim:remove_particle(small)
assert(sim:time_step() == short, "kept after the removal: " .. sim:time_step())
sim:set { time_step = 0 }
assert(sim:time_step() == big, "chosen afresh: " .. sim:time_step() .. " against " .. big)
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: sim:contact_parameters reports the surface energy in effect", "[lua][contact]") {
  // A JKR pair given no surface_energy takes the mean of its materials' values
  // (ThorntonJkr::surface_energy_in); its own value, when given, is reported as given.
  auto r = run_scene(R"(
local sim = simulation { dimension = 3 }
sim:material { name = "a", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.1 }
sim:material { name = "b", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.3 }
sim:contact { "a", "a", model = "thornton_jkr", friction = 0.3 }
sim:contact { "a", "b", model = "thornton_jkr", friction = 0.3 }
sim:contact { "b", "b", model = "thornton_jkr", friction = 0.3, surface_energy = 0.05 }
local function gamma(x, y) return sim:contact_parameters(x, y).surface_energy end
assert(gamma("a", "a") == 0.1, "a-a: " .. gamma("a", "a"))
assert(math.abs(gamma("b", "a") - 0.2) < 1e-15, "a-b, the materials' mean: " .. gamma("b", "a"))
assert(gamma("b", "b") == 0.05, "b-b, its own: " .. gamma("b", "b"))
)");
  CHECK(r.error == "");
}

TEST_CASE("lua: sim:wall gives back each wall's geometry as added, resolved", "[lua]") {
  auto r = run_scene(R"(local sim = simulation { dimension = 3 }
sim:material { name = "steel", density = 0 }
local function near(a, b) return math.abs(a - b) < 1e-12 end
local function same(v, w) for k = 1, 3 do if not near(v[k], w[k]) then return false end end return true end
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 2 }, material = "steel" }
sim:wall_plane { name = "plate", point = { 0, 0, 1 }, normal = { 0, 0, -1 }, size = { 0.2, 0.1 },
                 side = { 0, 1, 0 }, material = "steel" }
sim:wall_cylinder { name = "tube", center = { 0, 0, 0 }, axis = { 0, 0, 1 }, radius = 0.3, inside = false,
                    bounds = { -0.1, 0.2 }, material = "steel" }
sim:wall_disk { name = "orifice", center = { 0, 0, -1 }, normal = { 1, 0, 0 }, radius = 0.5,
                inner_radius = 0.1, material = "steel" }
sim:wall_cone { name = "hopper", center = { 0, 0, 2 }, axis = { 0, 3, 0 }, bounds = { 0, 0.4 },
                radii = { 0.05, 0.25 }, material = "steel" }
local floor = sim:wall("floor")
assert(same(floor.normal, { 0, 0, 1 }) and floor.size == nil, "floor")
local plate = sim:wall("plate")
assert(plate.finite and same(plate.normal, { 0, 0, -1 }), "plate normal")
assert(near(plate.size[1], 0.2) and near(plate.size[2], 0.1) and same(plate.side, { 0, 1, 0 }), "plate size, side")
local tube = sim:wall("tube")
assert(tube.inside == false and near(tube.radius, 0.3) and same(tube.axis, { 0, 0, 1 }), "tube")
assert(near(tube.bounds[1], -0.1) and near(tube.bounds[2], 0.2), "tube bounds")
local disk = sim:wall("orifice")
assert(same(disk.normal, { 1, 0, 0 }) and near(disk.radius, 0.5) and near(disk.inner_radius, 0.1), "disk")
local cone = sim:wall("hopper")
assert(same(cone.axis, { 0, 1, 0 }) and near(cone.radii[1], 0.05) and near(cone.radii[2], 0.25), "cone radii")
assert(near(cone.bounds[1], 0) and near(cone.bounds[2], 0.4) and cone.radius == nil, "cone bounds")
)");
  CHECK(r.error == "");
}
