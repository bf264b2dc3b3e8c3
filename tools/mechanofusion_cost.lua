-- Computing time against loading (dissertation Fig. 4.4): the CPU time one
-- simulated second of the Mechanofusion base case costs, for several particle
-- counts in the same chamber, with and without the diagnostics the studies
-- attach. The dissertation found its time growing faster than N^2; with
-- neighbour lists the work per step is proportional to N.
--
--   granule run tools/mechanofusion_cost.lua -D out=docs/data/mechanofusion_cost.csv --threads 1
--
-- Each case: build, settle `settle` s, then time `measure` s of simulated
-- time with os.clock (this process's CPU time), `repeats` times, keeping the
-- fastest (the machine is shared). Writes one CSV row per case.
local mf = require "granule.mechanofusion"

local p = parameters {
  loadings = { default = "250,500,1000,1500,2000", doc = "particle counts, comma-separated" },
  settle = { default = 2e-3, unit = "s", doc = "simulated time before timing" },
  measure = { default = 3e-3, unit = "s", doc = "simulated time timed" },
  repeats = { default = 2, unit = "-", doc = "timed stretches per case (the fastest is kept)" },
  every = { default = 40, unit = "-", doc = "steps between diagnostic samples (as the studies)" },
  out = { default = "mechanofusion_cost.csv", doc = "CSV written" },
}

local rows = {}
for item in p.loadings:gmatch("[^,%s]+") do
  local n = tonumber(item)
  if not n or n < 1 or n ~= math.floor(n) then error("loadings: '" .. item .. "' is not a particle count") end
  for _, diagnostics in ipairs { false, true } do
    local sim, geo = mf.build { particles = n }
    sim:run { duration = p.settle }
    if diagnostics then mf.attach_diagnostics(sim, geo, { every = p.every, window = p.measure }) end
    local best = math.huge
    for _ = 1, p.repeats do
      local start = os.clock()
      sim:run { duration = p.measure }
      best = math.min(best, os.clock() - start)
    end
    local steps = p.measure / sim:time_step()
    rows[#rows + 1] = string.format("%d,%s,%.6g,%.6g", n, diagnostics and "yes" or "no", best / p.measure,
      best / steps / n * 1e9)
    print(string.format("particles=%d diagnostics=%s cpu_seconds_per_simulated_second=%.4g ns_per_particle_step=%.4g",
      n, diagnostics and "yes" or "no", best / p.measure, best / steps / n * 1e9))
    sim:close()
  end
end
local f = assert(io.open(p.out, "w"))
f:write("particles,diagnostics,cpu_seconds_per_simulated_second,ns_per_particle_step\n")
f:write(table.concat(rows, "\n"), "\n")
f:close()
print("wrote " .. p.out)
