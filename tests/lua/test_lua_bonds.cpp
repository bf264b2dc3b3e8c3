// sim:bond and sim:bond_counts from a scene (src/lua/wrap_bonds.cpp): on a
// settled cluster sim:bond bonds exactly the pairs that touch (counted in
// Lua from the particles' positions), never a pair twice, and refuses every
// bad parameter by name.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <lua.hpp>
#include <string>

#include "lua/scene.hpp"

using namespace granule;

namespace {
// Runs `source` as a scene file with strict globals; the error ("" = ok).
std::string run_scene(const std::string& source) {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path() / "granule_lua_tests";
  std::filesystem::create_directories(dir);
  const std::string tag = "bond_" + std::to_string(getpid()) + "_" + std::to_string(++counter);
  const std::string path = (dir / (tag + ".lua")).string();
  std::ofstream(path) << source;
  lua::SceneContext ctx;
  ctx.scene_path = path;
  ctx.output_path = (dir / (tag + ".h5")).string();
  ctx.quiet = true;
  lua_State* L = lua::new_state(&ctx);
  lua::make_globals_strict(L);
  const std::string error = lua::run_file(L, path);
  lua_close(L);
  std::filesystem::remove(path);
  std::filesystem::remove(ctx.output_path);
  return error;
}
}  // namespace

TEST_CASE("lua: sim:bond bonds the touching pairs of a settled cluster", "[bond][lua]") {
  const char* scene = R"(
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.3, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.3, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:wall_plane { name = "left", point = { -0.004, 0 }, normal = { 1, 0 }, material = "steel" }
sim:wall_plane { name = "right", point = { 0.004, 0 }, normal = { -1, 0 }, material = "steel" }
sim:gravity { 0, -9.81 }
sim:fill { region = { box = { lo = { -0.0035, 0.0005 }, hi = { 0.0035, 0.014 } } }, count = 30,
           radius = 5e-4, material = "glass", seed = 3, overlap = false }
sim:run { duration = 0.15 }
-- The touching pairs, from the positions.
local ids = sim:particles()
local touching = 0
for a = 1, #ids do
  local p = sim:particle(ids[a])
  for b = a + 1, #ids do
    local q = sim:particle(ids[b])
    local dx, dy = p.position[1] - q.position[1], p.position[2] - q.position[2]
    if math.sqrt(dx * dx + dy * dy) <= p.radius + q.radius then touching = touching + 1 end
  end
end
assert(touching > 20, "the cluster has settled into contact: " .. touching)
local made = sim:bond { materials = { "glass" }, normal_stiffness = 1e9, shear_stiffness = 4e8,
                        tensile_strength = 1e7, shear_strength = 1e7 }
assert(made == touching, string.format("bonded %d pairs, %d touch", made, touching))
local counts = sim:bond_counts()
assert(counts.intact == made and counts.broken == 0, "counts")
-- No pair twice; a filter no particle matches bonds none.
assert(sim:bond { normal_stiffness = 1e9, shear_stiffness = 4e8, tensile_strength = 1e7,
                  shear_strength = 1e7 } == 0, "a second call bonded again")
assert(sim:bond { materials = { "glass", "steel" }, normal_stiffness = 1e9, shear_stiffness = 4e8,
                  tensile_strength = 1e7, shear_strength = 1e7 } == 0, "glass-steel")
-- Strong bonds hold the resting cluster.
sim:run { duration = 0.01 }
assert(sim:bond_counts().intact == made, "bonds broke at rest")

-- Every bad parameter is refused by name.
local good = { normal_stiffness = 1e9, shear_stiffness = 4e8, tensile_strength = 1e7,
               shear_strength = 1e7 }
local function refused(change, needle)
  local t = {}
  for k, v in pairs(good) do t[k] = v end
  for k, v in pairs(change) do t[k] = v end
  if change.drop then t[change.drop] = nil; t.drop = nil end
  local ok, message = pcall(sim.bond, sim, t)
  assert(not ok, "accepted: " .. needle)
  assert(message:find(needle, 1, true), "'" .. needle .. "' not in: " .. message)
end
refused({ normal_stiffness = -1 }, "'normal_stiffness'")
refused({ shear_stiffness = 0 / 0 }, "'shear_stiffness'")
refused({ tensile_strength = math.huge }, "'tensile_strength'")
refused({ shear_strength = 0 }, "'shear_strength'")
refused({ radius_multiplier = -2 }, "'radius_multiplier'")
refused({ gap = -1e-6 }, "'gap'")
refused({ drop = "tensile_strength" }, "tensile_strength")
refused({ materials = { "sand" } }, "sand")
refused({ materials = { "glass", "steel", "glass" } }, "'materials'")
refused({ normal_stifness = 1 }, "normal_stiffness")
)";
  CHECK(run_scene(scene) == "");
}
