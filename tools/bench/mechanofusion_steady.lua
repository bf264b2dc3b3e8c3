-- Steady-state speed of the 2D Mechanofusion base case (Table 4.1, Walton-Braun):
-- settle for `settle` seconds, save a checkpoint there, then time `measure`
-- seconds and print particle-steps/s (wall clock) with the per-stage breakdown.
--   build/granule run tools/bench/mechanofusion_steady.lua --quiet
-- Later runs can skip the settling: granule run ... --restart mechanofusion_settled.chk.h5
-- `-D csv=FILE` also appends the timed window as one row (docs/performance.md
-- lists the columns).
local p = parameters {
  settle = { default = 0.05, unit = "s" },
  measure = { default = 0.01, unit = "s" },
  model = { default = "walton_braun", doc = "walton_braun | linear" },
  particles = { default = 1500 },
  checkpoint = { default = "mechanofusion_settled.chk.h5", doc = "written after settling" },
  skin = { default = 0, unit = "m", doc = "neighbour-list skin; 0 = automatic" },
  csv = { default = "", doc = "also append the timed window as one row to this CSV file" },
}
local granule = require "granule"
local bench = require "granule.bench"
-- A binary built elsewhere loads its own tree's library: say so, not "nil".
assert(bench.result_line, "granule.bench lacks result_line (an older lua/): set GRANULE_LUA_PATH to this tree's lua/")
local columns = { "model", "particles", "steps", "pair_contacts", "wall_contacts", "list_rebuilds", "wall_s",
                  "particle_steps_per_s" }
for _, c in ipairs(bench.stage_columns) do columns[#columns + 1] = c end
if p.csv ~= "" then bench.check_csv(p.csv, columns) end
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
local function law(mu)
  if p.model == "linear" then
    return { model = "linear", k_normal = 2e4, restitution = 0.85, friction = mu }
  end
  return { model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = mu }
end
local pp, pw = law(0.4), law(0.5)
pp[1], pp[2], pw[1], pw[2] = "powder", "powder", "powder", "steel"
sim:contact(pp)
sim:contact(pw)
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 12.5e-3, angular_velocity = granule.rpm(2000), material = "steel" }
sim:wall_cylinder { name = "inner", center = { 5.9e-3, 0 }, radius = 5e-3, inside = false, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 12.5e-3 } }, count = p.particles, radius = 0.2e-3, material = "powder", seed = 1, max_speed = 0.01 }
sim:run { duration = p.settle }
if p.checkpoint ~= "" then sim:save_checkpoint(p.checkpoint) end
-- One step first: a restarted bench loads its checkpoint here, so the settings below apply.
sim:run { steps = 1 }
if p.skin > 0 then sim:set { skin = p.skin } end
local t0, tm0, rebuilds0 = wall_time(), sim:timings(), sim:stats().list_rebuilds
local r = sim:run { duration = p.measure }
local wall = wall_time() - t0
local stage = bench.stage_seconds(sim, tm0)
local s = sim:stats()
print(string.format("steps %d wall %.2f s  -> %.3g particle-steps/s  contacts pp %d pw %d"
  .. "  candidates %d  rebuilds %d",
  r.steps, wall, p.particles * r.steps / wall, s.contacts_particle, s.contacts_wall,
  s.candidate_pairs, s.list_rebuilds - rebuilds0))
print(string.format("neighbor %.2f force %.2f diagnostics %.2f integrate %.2f hooks %.2f",
  stage.neighbour_s, stage.contacts_s, stage.diagnostics_s, stage.integrate_s, stage.hooks_s))
if p.csv ~= "" then
  local row = { model = p.model, particles = p.particles, steps = r.steps, pair_contacts = s.contacts_particle,
                wall_contacts = s.contacts_wall, list_rebuilds = s.list_rebuilds - rebuilds0, wall_s = wall,
                particle_steps_per_s = p.particles * r.steps / wall }
  for k, v in pairs(stage) do row[k] = v end
  bench.append_csv(p.csv, columns, row)
end
