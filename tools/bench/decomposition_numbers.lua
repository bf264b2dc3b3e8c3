-- The single-node numbers docs/performance.md uses to sketch a domain
-- decomposition over MPI ranks: on the settled dense 3D box of
-- tools/bench/box3d_compare.lua (the same walls, contacts and shaking floor),
-- particle-steps per second, neighbour-list rebuilds and their cost, candidate
-- pairs and contacts per particle, and resident memory per particle.
--   /usr/bin/python3 tools/bench/compare.py --case box3d --threads 1   # writes bench_work/box_50x50x40_settled0.02s.h5
--   build/granule run tools/bench/decomposition_numbers.lua -D state=bench_work/box_50x50x40_settled0.02s.h5 --threads 1 -q
local bench = require "granule.bench"
local p = parameters(bench.parameters {
  state = { default = "", doc = "settled box from tools/bench/compare.py (box_<side>x<side>x<layers>_settled<time>s.h5)" },
  per_side = { default = 50, doc = "spheres per side of the box the state holds" },
  steps = { default = 2000 },
})
assert(p.state ~= "", "give -D state=FILE (a settled box written by tools/bench/compare.py)")

-- Resident memory of this process (Linux), kB.
local function rss_kb()
  local f = io.open("/proc/self/status")
  if not f then return 0 end
  local text = f:read("a")
  f:close()
  return tonumber(text:match("VmRSS:%s*(%d+)")) or 0
end

local rss_before = rss_kb()
local sim = bench.shaken_box(bench.options(p))
sim:load_particles { file = p.state }
local n = #sim:particles()
local contacts, samples = 0, 0
sim:every { steps = 100, function(s)
  contacts = contacts + s:stats().contacts_particle
  samples = samples + 1
end }
local t_first = wall_time()
sim:run { steps = 1 }  -- lists built from scratch, histories allocated
local first_step = wall_time() - t_first
local rss_running = rss_kb()
local s0, t0, tm0 = sim:stats(), wall_time(), sim:timings()
sim:run { steps = p.steps }
local wall = wall_time() - t0
local s1, tm = sim:stats(), sim:timings()
local rebuilds = s1.list_rebuilds - s0.list_rebuilds
local neighbour = tm.neighbor - tm0.neighbor
local step_time = wall / p.steps
print(string.format("particles=%d steps=%d wall_s=%.3f particle_steps_per_s=%.4g", n, p.steps, wall,
                    n * p.steps / wall))
print(string.format("stages_s: neighbour=%.3f contacts=%.3f integrate=%.3f hooks=%.3f", neighbour,
                    tm.force - tm0.force, tm.integrate - tm0.integrate, tm.hooks - tm0.hooks))
-- A build from scratch (cells, lists, contact slots: the first step less a steady one)
-- against the steady step; the rebuilds during the run also carry histories over.
print(string.format("first_step_s=%.4g build_from_scratch_s=%.4g build_in_steps=%.1f", first_step,
                    first_step - step_time, (first_step - step_time) / step_time))
print(string.format("rebuilds=%d steps_per_rebuild=%.1f rebuild_s=%.4g rebuild_in_steps=%.2f",
                    rebuilds, p.steps / math.max(rebuilds, 1), neighbour / math.max(rebuilds, 1),
                    neighbour / math.max(rebuilds, 1) / step_time))
print(string.format("candidate_pairs_per_particle=%.2f pair_contacts_per_particle=%.2f",
                    s1.candidate_pairs / n, contacts / math.max(samples, 1) / n))
print(string.format("rss_mb=%.1f bytes_per_particle=%.0f (resident growth from before the scene to the first step)",
                    rss_running / 1024, (rss_running - rss_before) * 1024 / n))
