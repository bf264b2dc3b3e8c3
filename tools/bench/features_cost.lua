-- What an unused feature costs: the same scene (the 2D Mechanofusion base case of
-- Table 4.1 with linear or Walton-Braun contacts, 1500 particles, chamber at
-- 2000 rpm) with and without each feature declared, and with every diagnostic
-- attached. A scene should pay only for what it names (docs/features_cost.md), so every
-- "declared but unused" row should read 1.00 within the noise.
--
--   build/granule run tools/bench/features_cost.lua --quiet [-D steps=20000 -D rounds=3]
--   tools/bench/features_cost.sh    (also runs the specialised-loop comparison)
--
-- Each variant builds its scene, settles it for `settle` steps (the overlapping fill
-- of SPEC 2 flies apart and flows), then times `steps` steps; variants take turns
-- over `rounds` rounds and the best time of each is kept. The table gives
-- particle-steps/s and the time relative to the plain scene (> 1: slower).
local granule = require "granule"
local p = parameters {
  steps = { default = 20000, doc = "timed steps per variant and round" },
  settle = { default = 20000, doc = "steps before timing" },
  rounds = { default = 3 },
  particles = { default = 1500 },
  model = { default = "linear", doc = "linear | walton_braun" },
  only = { default = "", doc = "comma-separated variant names (default: all)" },
  csv = { default = "", doc = "also write the table to this CSV file" },
}

local function law(mu)
  if p.model == "linear" then return { model = "linear", k_normal = 2e4, restitution = 0.85, friction = mu } end
  return { model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = mu }
end

-- The variants: what each adds to (or takes from) the plain scene.
local variants = {
  { name = "plain", doc = "the base case as it is" },
  { name = "adhesive_pair_unused", doc = "a JKR material pair declared, no particle of it",
    setup = function(sim)
      sim:material { name = "glue", density = 1200, young = 1e8, poisson = 0.3, surface_energy = 1 }
      sim:contact { "glue", "glue", model = "thornton_jkr", friction = 0.4 }
      sim:contact { "glue", "powder", model = "thornton_jkr", friction = 0.4 }
      sim:contact { "glue", "steel", model = "thornton_jkr", friction = 0.4 }
    end },
  { name = "gravity_zero", doc = "gravity declared as (0, 0)",
    setup = function(sim) sim:gravity { 0, 0 } end },
  { name = "central_field_zero", doc = "central field declared with strength 0",
    setup = function(sim) sim:central_field { point = { 0, 0 }, strength = 0 } end },
  { name = "moving_plane_far", doc = "a plane wall 1 m away moving at 1 mm/s",
    setup = function(sim)
      sim:wall_plane { name = "far", point = { 0, -1 }, normal = { 0, 1 }, velocity = { 0, 1e-3 },
                       material = "steel" }
    end },
  { name = "empty_hook", doc = "a Lua hook every 1000 steps that does nothing",
    setup = function(sim) sim:every { steps = 1000, function() end } end },
  { name = "wall_force_both", doc = "wall_force on the inner piece and on the chamber",
    setup = function(sim)
      sim:diagnostic("wall_force", { wall = "inner_piece", window = 1e-3 })
      sim:diagnostic("wall_force", { wall = "chamber", window = 1e-3 })
    end },
  { name = "zones", doc = "the zones diagnostic (4.3-4.6), defaults",
    setup = function(sim) sim:diagnostic("zones", {}) end },
  { name = "areas", doc = "the areas diagnostic (4.4.2), defaults",
    setup = function(sim) sim:diagnostic("areas", {}) end },
  { name = "contact_peaks", doc = "the contact_peaks diagnostic (contact events every step)",
    setup = function(sim) sim:diagnostic("contact_peaks", {}) end },
  { name = "diagnostics_all", doc = "every registered diagnostic: wall_force x2, zones, areas, contact_peaks",
    setup = function(sim)
      sim:diagnostic("wall_force", { wall = "inner_piece", window = 1e-3 })
      sim:diagnostic("wall_force", { wall = "chamber", window = 1e-3 })
      sim:diagnostic("zones", {})
      sim:diagnostic("areas", {})
      sim:diagnostic("contact_peaks", {})
    end },
  { name = "record_contacts", doc = "record_contacts = true (the contact log every step)",
    options = { record_contacts = true } },
  { name = "friction_off", doc = "friction 0 everywhere (no torques: spins not integrated)",
    friction = 0 },
  { name = "rolling_pair_unused", doc = "a pair with rolling friction declared, no particle of it",
    setup = function(sim)
      sim:material { name = "grit", density = 1200, young = 3e9, poisson = 0.35 }
      local g = law(0.4)
      g[1], g[2], g.rolling_friction = "grit", "grit", 0.1
      sim:contact(g)
    end },
  { name = "rolling_on", doc = "rolling_friction 0.1 (EPSD) on both pairs (a feature in use, for scale)",
    rolling = 0.1 },
  { name = "gravity_on", doc = "gravity 9.81 m/s^2 (a feature in use, for scale)",
    setup = function(sim) sim:gravity { 0, -9.81 } end },
}

local wanted
if p.only ~= "" then
  wanted = {}
  for name in p.only:gmatch("[^,]+") do wanted[name] = true end
end

local function build(v)
  local sim = simulation { dimension = 2, record_contacts = v.options and v.options.record_contacts or nil }
  sim:set { threads = 1 }
  -- Elastic constants are given in every variant (the linear law ignores them; the
  -- JKR law of the adhesive variant needs them), so the scenes differ only in the feature.
  sim:material { name = "powder", density = 1200, young = 3e9, poisson = 0.35 }
  sim:material { name = "steel", density = 7800, young = 2e11, poisson = 0.3 }
  local pp, pw = law(v.friction or 0.4), law(v.friction or 0.5)
  pp[1], pp[2], pw[1], pw[2] = "powder", "powder", "powder", "steel"
  pp.rolling_friction, pw.rolling_friction = v.rolling, v.rolling
  sim:contact(pp)
  sim:contact(pw)
  sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 12.5e-3, angular_velocity = granule.rpm(2000),
                      material = "steel" }
  sim:wall_cylinder { name = "inner_piece", center = { 5.9e-3, 0 }, radius = 5e-3, inside = false,
                      material = "steel" }
  sim:fill { region = { circle = { center = { 0, 0 }, radius = 12.5e-3 } }, count = p.particles, radius = 0.2e-3,
             material = "powder", seed = 1, max_speed = 0.01 }
  if v.setup then v.setup(sim) end
  sim:run { steps = p.settle }
  return sim
end

local best, rebuilds = {}, {}
local active = {}
for _, v in ipairs(variants) do
  if not wanted or wanted[v.name] then active[#active + 1] = v end
end
local sims = {}
for _, v in ipairs(active) do sims[v.name] = build(v) end
for _ = 1, p.rounds do
  for _, v in ipairs(active) do
    local sim = sims[v.name]
    local r0 = sim:stats().list_rebuilds
    local t0 = wall_time()
    sim:run { steps = p.steps }
    local t = wall_time() - t0
    if not best[v.name] or t < best[v.name] then best[v.name] = t end
    rebuilds[v.name] = sim:stats().list_rebuilds - r0
  end
end

local base = best.plain or best[active[1].name]
local rows = {}
print(string.format("features_cost: %s contacts, %d particles, %d steps x %d rounds (best kept)", p.model,
  p.particles, p.steps, p.rounds))
print("| variant | particle-steps/s | time / plain | rebuilds | what it declares |")
print("|---|---|---|---|---|")
for _, v in ipairs(active) do
  local rate = p.particles * p.steps / best[v.name]
  local ratio = best[v.name] / base
  rows[#rows + 1] = { v.name, rate, ratio, rebuilds[v.name], v.doc }
  print(string.format("| %s | %.3g | %.3f | %d | %s |", v.name, rate, ratio, rebuilds[v.name], v.doc))
end
if p.csv ~= "" then
  local f = assert(io.open(p.csv, "w"))
  f:write("variant,particle_steps_per_s,time_over_plain,rebuilds,doc\n")
  for _, r in ipairs(rows) do f:write(string.format("%s,%.6g,%.6f,%d,\"%s\"\n", r[1], r[2], r[3], r[4], r[5])) end
  f:close()
end
