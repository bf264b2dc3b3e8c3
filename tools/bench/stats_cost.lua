-- What one sim:stats() call costs in a callback, on one process or spread
-- over ranks (docs/parallel.md): the 2D Mechanofusion base case (Table 4.1,
-- Walton-Braun) from a settled state, stretches of `steps` steps without the
-- call and with it made every step, in turn; the difference per call.
--   build/granule run tools/bench/mechanofusion_compare.lua -D save=bench_work/mf_state.h5
--   mpirun --allow-run-as-root -np 2 build/granule run tools/bench/stats_cost.lua \
--       -D state=bench_work/mf_state.h5 --threads 1 -q
local granule = require "granule"
local p = parameters {
  state = { default = "", doc = "the settled state (mechanofusion_compare.lua -D save=...)" },
  steps = { default = 10000, doc = "steps in each timed stretch, without and with the call" },
  rounds = { default = 3, doc = "stretches of each" },
}
assert(p.state ~= "", "give -D state=FILE (mechanofusion_compare.lua -D save=FILE writes one)")
local sim = simulation { dimension = 2, time_step = 6.6936e-8 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.4 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 12.5e-3, angular_velocity = granule.rpm(2000),
                    material = "steel" }
sim:wall_cylinder { name = "inner", center = { 5.9e-3, 0 }, radius = 5e-3, inside = false, material = "steel" }
sim:load_particles { file = p.state }
local calling, sum = false, 0
sim:every { steps = 1, function(s)
  if calling then sum = sum + s:stats().kinetic_energy_translational end
end }
sim:run { steps = 100 }
-- Rounds without and with the call in turn; the fastest of each (the host's
-- speed drifts more than a call costs).
local without, with = math.huge, math.huge
for _ = 1, p.rounds do
  for _, call in ipairs { false, true } do
    calling = call
    local t0 = wall_time()
    sim:run { steps = p.steps }
    local took = wall_time() - t0
    if call then with = math.min(with, took) else without = math.min(without, took) end
  end
end
assert(sum > 0, "stats() gave no kinetic energy")
print(string.format("stats() per call: %.1f us (%d steps: without the call %.3f s, with it %.3f s, fastest of %d rounds)",
  (with - without) / p.steps * 1e6, p.steps, without, with, p.rounds))
