-- The agglomerate bindings on hand-built configurations: a snapshot round trip
-- through sim:load_particles, bonds and fragments of a known contact graph,
-- the breakage ratios after a bond is removed by hand, and the refusals of bad
-- input, each naming what is wrong. Every assertion can fail.
local agglomerate = require "granule.agglomerate"

local function refused(pattern, f, ...)
  local ok, message = pcall(f, ...)
  assert(not ok, "expected an error matching '" .. pattern .. "'")
  assert(string.find(message, pattern, 1, true), "error '" .. tostring(message) .. "' lacks '" .. pattern .. "'")
end

-- Five equal discs: a touching chain 1-2-3, a touching pair 4-5 (overlap 1 %).
local r = 1e-3
local function build(record)
  local sim = simulation { dimension = 2, record_contacts = record }
  sim:material { name = "glass", density = 2500 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.5 }
  local x = { 0, 1.98 * r, 3.96 * r, 20 * r, 21.98 * r }
  local ids = {}
  for k = 1, 5 do ids[k] = sim:add_particle { position = { x[k], 0 }, radius = r, material = "glass" } end
  sim:run { steps = 1 }
  return sim, ids
end

local sim, ids = build(true)
local bonds = sim:bonds { material = "glass" }
assert(#bonds == 3, "bonds: " .. #bonds)
local f = sim:fragments {}
assert(f.count == 2, "fragments: " .. f.count)
assert(f.labels[ids[1]] == 1 and f.labels[ids[3]] == 1 and f.labels[ids[4]] == 2, "labels: chain first, pair second")
assert(f.members[1] == 3 and f.members[2] == 2)

-- Break the pair by hand: one of three bonds broken, the pair now two singles.
sim:set_position(ids[5], { 30 * r, 0 })
sim:run { steps = 1 }
local b = sim:breakage { initial_bonds = bonds, labels = true }
assert(b.broken_bonds == 1 and b.initial_bonds == 3, "broken " .. b.broken_bonds)
assert(math.abs(b.damage_ratio - 1 / 3) < 1e-12, "damage ratio " .. b.damage_ratio)
assert(b.fragments == 3 and b.large == 3 and b.debris_ratio == 0, "each disc is 20 % of the mass: large")
assert(math.abs(b.largest_fraction - 0.6) < 1e-12, "largest fraction " .. b.largest_fraction)
local tiny = sim:breakage { initial_bonds = bonds, large = 0.7, debris = 0.25, fines = 0.21 }
assert(tiny.medium == 1 and tiny.small == 2 and tiny.fines == 2 and math.abs(tiny.debris_ratio - 0.4) < 1e-12,
  "custom classes")
local only_chain = sim:breakage { initial_bonds = bonds, particles = { ids[1], ids[2], ids[3] } }
-- The pair's broken bond is not the chain's (both its particles are still in the scene,
-- outside the selection): the chain has 2 bonds, none broken.
assert(only_chain.fragments == 1 and only_chain.initial_bonds == 2 and only_chain.broken_bonds == 0,
  "selection by ids: " .. only_chain.initial_bonds .. " bonds, " .. only_chain.broken_bonds .. " broken")
-- A particle removed since counts its bonds broken.
local removed_sim, removed_ids = build(true)
local removed_bonds = removed_sim:bonds { material = "glass" }
removed_sim:remove_particle(removed_ids[5])
local without = removed_sim:breakage { initial_bonds = removed_bonds }
assert(without.initial_bonds == 3 and without.broken_bonds == 1, "a removed particle's bond is broken")
-- One the scene never had is a slip, refused (it would count as broken).
refused("names particle 999, which this scene never had (its ids run from 0 to 4)",
  function() removed_sim:breakage { initial_bonds = { { removed_ids[1], 999 } } } end)
refused("'initial_bonds'[2] names particle 5", function()
  removed_sim:breakage { initial_bonds = { { removed_ids[1], removed_ids[2] }, { 5, removed_ids[2] } } }
end)

-- Round trip: write a snapshot, load it into a new scene under another material name.
sim:output { file = "agglomerate_api_check.h5" }
sim:snapshot()
sim:close()
local copy = simulation { dimension = 2 }
copy:material { name = "sand", density = 2500 }
copy:contact { "sand", "sand", model = "linear", k_normal = 1e3, restitution = 0.5 }
local loaded = copy:load_particles { file = "agglomerate_api_check.h5", material_map = { glass = "sand" },
                                     offset = { 1, 2 }, velocity = { 0.5, 0 } }
assert(#loaded == 5, "loaded " .. #loaded)
for k, id in ipairs(loaded) do
  local a, c = sim:particle(ids[k]), copy:particle(id)
  assert(math.abs(c.position[1] - a.position[1] - 1) < 1e-15 and math.abs(c.position[2] - a.position[2] - 2) < 1e-15,
    "position of particle " .. k)
  assert(c.radius == a.radius and c.material == "sand" and math.abs(c.velocity[1] - a.velocity[1] - 0.5) < 1e-15)
end

-- Refusals.
refused("not recorded", function() build(false):bonds {} end)
refused("no such file", function() copy:load_particles { file = "no_such_agglomerate.h5" } end)
refused("material_map names 'glas'", function()
  copy:load_particles { file = "agglomerate_api_check.h5", material_map = { glas = "sand" } }
end)
refused("saved material 'glass'", function()
  simulation { dimension = 2 }:load_particles { file = "agglomerate_api_check.h5" }
end)
refused("holds no contact histories", function()
  copy:load_particles { file = "agglomerate_api_check.h5", material_map = { glass = "sand" }, histories = true }
end)
refused("exists already", function()
  sim:save_contact_histories { file = "agglomerate_api_check.h5" }
  sim:save_contact_histories { file = "agglomerate_api_check.h5" }
end)
refused("holds a 2D snapshot, this scene is 3D", function()
  local s3 = simulation { dimension = 3 }
  s3:material { name = "glass", density = 2500 }
  s3:load_particles { file = "agglomerate_api_check.h5" }
end)
refused("'graph' must be", function() sim:breakage { initial_bonds = bonds, graph = "bonds" } end)
refused("have no parallel bonds", function() sim:breakage { initial_bonds = bonds, graph = "parallel_bonds" } end)
assert(sim:breakage { initial_bonds = bonds }.parallel_damage_ratio == nil, "parallel bond counts without parallel bonds")
refused("'initial_bonds' is required", function() sim:breakage {} end)
refused("must be a pair", function() sim:breakage { initial_bonds = { { 1 } } } end)
refused("bonded to itself", function() sim:breakage { initial_bonds = { { 2, 2 } } } end)
refused("fines <= debris", function() sim:breakage { initial_bonds = bonds, fines = 0.5 } end)
refused("not both", function() sim:bonds { material = "glass", particles = { 1 } } end)
refused("does not exist", function() sim:bonds { particles = { 999 } } end)
refused("'factor'", function() sim:scale_velocities { factor = -1 } end)
refused("unknown option 'surface_enrgy' (did you mean 'surface_energy'?)", function()
  agglomerate.prepare(simulation { dimension = 2, record_contacts = true }, { surface_enrgy = 1 })
end)
refused("'field_strength' must be > 0 [m/s^2]", function()
  agglomerate.prepare(simulation { dimension = 2, record_contacts = true }, { field_strength = -1 })
end)
refused("too small for 217 primaries", function()
  agglomerate.prepare(simulation { dimension = 2, record_contacts = true }, { generation_diameter = 50e-6 })
end)
local tests = require "granule.agglomerate_tests"
refused("unknown kind 'shear'", function() tests.run(simulation { dimension = 2 }, "shear", {}) end)
refused("'file' is required", function() tests.run(simulation { dimension = 2 }, "wall", {}) end)
refused("'velocity' must be > 0 [m/s]", function()
  tests.run(simulation { dimension = 2 }, "wall", { file = "x.h5", velocity = 0 })
end)
print("agglomerate_api_check ok")
