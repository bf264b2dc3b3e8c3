-- Is the cost linear in particles and contacts? The dense shaken 3D box of
-- tools/bench/box3d_compare.lua (spheres on a touching cubic lattice, four side
-- walls, a floor shaken at 50 Hz, linear contacts with friction) at several
-- sizes, each timed over `steps` steps after `warmup` steps, in one run:
-- particle-steps/s and the time per contact should stay flat as N grows, and
-- so should the set-up's time per sphere (the box built and its spheres added
-- one by one with sim:add_particle, before the first step).
-- (The lattice is still settling, so lists are rebuilt often: these runs are
-- slower per particle than the settled box of compare.py, at every size alike.)
--   build/granule run tools/bench/scaling.lua -q
--   build/granule run tools/bench/scaling.lua -D sides=10,20,30,40,50 -D layers=40 -q
-- `-D csv=FILE` also appends one row per size (spheres, contacts, wall and
-- stage seconds: docs/performance.md lists the columns).
local p = parameters {
  sides = { default = "12,18,25,35,50", doc = "spheres per side of the box, one run each" },
  layers = { default = 40 },
  radius = { default = 1e-3, unit = "m" },
  steps = { default = 300 },
  warmup = { default = 300 },
  csv = { default = "", doc = "also append one row per size to this CSV file" },
}
local r = p.radius
local bench = require "granule.bench"
-- A binary built elsewhere loads its own tree's library: say so, not "nil".
assert(bench.result_line, "granule.bench lacks result_line (an older lua/): set GRANULE_LUA_PATH to this tree's lua/")
local columns = { "spheres", "steps", "pair_contacts", "list_rebuilds", "wall_s", "particle_steps_per_s" }
for _, c in ipairs(bench.stage_columns) do columns[#columns + 1] = c end
if p.csv ~= "" then bench.check_csv(p.csv, columns) end
print("| spheres | pair contacts / sphere | list rebuilds / 100 steps | particle-steps/s | ns per step per sphere | ns per step per contact | set-up, us per sphere |")
print("|---|---|---|---|---|---|---|")
for side_text in string.gmatch(p.sides, "[^,]+") do
  local per_side = math.tointeger(tonumber(side_text))
  assert(per_side and per_side > 0, "sides: positive integers, got '" .. side_text .. "'")
  local box = { per_side = per_side, layers = p.layers, radius = r }
  local setup_start = wall_time()
  local sim = bench.shaken_box(box)
  bench.fill_lattice(sim, box)
  local setup = wall_time() - setup_start
  sim:run { steps = p.warmup }
  local contacts, samples = 0, 0
  sim:every { steps = 50, function(s)
    contacts, samples = contacts + s:stats().contacts_particle, samples + 1
  end }
  local rebuilds0 = sim:stats().list_rebuilds
  local t0, tm0 = wall_time(), sim:timings()
  sim:run { steps = p.steps }
  local wall = wall_time() - t0
  local stage = bench.stage_seconds(sim, tm0)
  local n = sim:stats().particles
  local mean_contacts = contacts / math.max(samples, 1)
  local rebuilds = sim:stats().list_rebuilds - rebuilds0
  print(string.format("| %d | %.2f | %.1f | %.3g | %.1f | %.1f | %.2f |", n, mean_contacts / n,
    100 * rebuilds / p.steps, n * p.steps / wall,
    1e9 * wall / (p.steps * n), 1e9 * wall / (p.steps * math.max(mean_contacts, 1)),
    1e6 * setup / n))
  if p.csv ~= "" then
    local row = { spheres = n, steps = p.steps, pair_contacts = mean_contacts,
                  list_rebuilds = rebuilds, wall_s = wall, particle_steps_per_s = n * p.steps / wall }
    for k, v in pairs(stage) do row[k] = v end
    bench.append_csv(p.csv, columns, row)
  end
end
