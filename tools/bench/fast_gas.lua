-- A fast, dilute flow for timing the pruned pair lists where they are noted
-- most often (docs/performance.md, "Pruned lists"): 8,000 spheres (r = 0.5
-- mm) at up to 3 m/s in a closed 3 cm box, no gravity, the lists rebuilt
-- every ~7 steps. 200 warm-up steps, then `steps` timed; prints one line.
--   build/granule run tools/bench/fast_gas.lua -D steps=3000 --threads 1 -q
local p = parameters {
  steps = { default = 3000 },
  count = { default = 8000 },
}
local side = 0.03
local sim = simulation { dimension = 3, time_step = 2e-6 }
sim:material { name = "g", density = 2500 }
sim:contact { "g", "g", model = "linear", k_normal = 1e4, restitution = 0.9, friction = 0.3 }
for axis = 1, 3 do
  local lo, hi, normal = { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 }
  hi[axis] = side
  normal[axis] = 1
  sim:wall_plane { name = "lo" .. axis, point = lo, normal = normal, material = "g" }
  normal[axis] = -1
  sim:wall_plane { name = "hi" .. axis, point = hi, normal = { normal[1], normal[2], normal[3] }, material = "g" }
end
sim:fill { region = { box = { lo = { 0, 0, 0 }, hi = { side, side, side } } }, count = p.count,
           radius = 0.5e-3, material = "g", seed = 3, max_speed = 3 }
sim:run { steps = 200 }
local st0, t0 = sim:stats(), wall_time()
sim:run { steps = p.steps }
local wall, st = wall_time() - t0, sim:stats()
print(string.format("fast gas: %.3g particle-steps/s, list rebuilds %d, prunes %d in %d steps",
  st.particles * p.steps / wall, st.list_rebuilds - st0.list_rebuilds,
  st.pair_list_prunes - st0.pair_list_prunes, p.steps))
