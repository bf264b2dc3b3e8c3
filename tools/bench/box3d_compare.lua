-- A dense shaken box of spheres in 3D for side-by-side timing against LAMMPS
-- and LIGGGHTS (tools/bench/compare.py): `per_side`^2 x `layers` spheres of
-- r = 1 mm start on a touching cubic lattice in a box with four side walls, fall
-- onto a floor that shakes vertically (amplitude `amplitude`, frequency
-- `frequency`), Hooke contacts with friction (`-D model=hertz_mindlin`: damped
-- Hertz-Mindlin, E = `young`, nu = `poisson`). Without `state` the scene
-- settles for `settle` s (rounded up to whole periods of the floor) and saves
-- the state; with `state` it loads it and times `steps` steps.
--   build/granule run tools/bench/box3d_compare.lua -D save=box_state.h5
--   build/granule run tools/bench/box3d_compare.lua -D state=box_state.h5 -D steps=1000 --threads 2
-- `-D out=FILE` then also writes the final state (to compare two builds' results);
-- `-D canonical=true` times the canonical order (sim:set { canonical_order = true }).
-- The timed run prints the stage times on stderr and one line on stdout for
-- compare.py (bench.result_line: wall and stage seconds, mean contacts).
local bench = require "granule.bench"
-- A binary built elsewhere loads its own tree's library: say so, not "nil".
assert(bench.result_line, "granule.bench lacks result_line (an older lua/): set GRANULE_LUA_PATH to this tree's lua/")
local p = parameters(bench.parameters {
  layers = { default = 40 },
  settle = { default = 0.02, unit = "s" },
  save = { default = "" },
  state = { default = "" },
  steps = { default = 1000 },
  out = { default = "" },  -- with state: write the state after the timed steps here
  pruning = { default = true, doc = "pruned pair lists (false: every candidate every step, for comparison)" },
  canonical = { default = false, doc = "canonical order: sums in particle-id order (docs/parallel.md)" },
})
local box = bench.options(p)
local sim = bench.shaken_box(box)
if p.state == "" then
  box.layers = p.layers
  bench.fill_lattice(sim, box)
  -- Whole periods of the floor, so the state is saved with the floor at rest at
  -- the bottom of its stroke, where every program's floor starts (granule.bench).
  local settle = p.settle
  if p.frequency > 0 then settle = math.max(1, math.ceil(p.settle * p.frequency - 1e-9)) / p.frequency end
  sim:run { duration = settle }
  assert(p.save ~= "", "give -D save=FILE to keep the settled state")
  sim:output { file = p.save, xdmf = false }
  sim:snapshot()
  sim:close()
  print("settled state written to " .. p.save)
  return
end
sim:load_particles { file = p.state }
if not p.pruning then sim:set { pruning = false } end
if p.canonical then sim:set { canonical_order = true } end
local contacts, pair_contacts, energy, samples = 0, 0, 0, 0
sim:every { steps = 100, function(s)
  local st = s:stats()
  contacts, pair_contacts = contacts + st.contacts_particle + st.contacts_wall, pair_contacts + st.contacts_particle
  energy = energy + st.kinetic_energy_translational  -- as LAMMPS's `ke`, for checking the flows agree
  samples = samples + 1
end }
local warm_up = wall_time()
sim:run { steps = 1 }
warm_up = wall_time() - warm_up
local t0, tm0, st0 = wall_time(), sim:timings(), sim:stats()
sim:run { steps = p.steps }
local wall = wall_time() - t0
-- The warm-up step prepared the scene and built the lists (the Morton re-sort,
-- the cell grid and, in canonical order, the sorts by id).
io.stderr:write(string.format("warm-up step (prepare, the lists built): %.4f s\n", warm_up))
local stage = bench.stage_seconds(sim, tm0)
local st = sim:stats()
io.stderr:write(string.format("stages [s]: neighbour %.3f contacts %.3f (of which walls %.3f, fixed-order sums %.3f) diagnostics %.3f integrate %.3f hooks %.3f; thread rebalances %d\n",
  stage.neighbour_s, stage.contacts_s, stage.walls_s, stage.sums_s, stage.diagnostics_s,
  stage.integrate_s, stage.hooks_s, st.thread_rebalances))
-- The pair loop's cost per pair contact (contact stage less walls and the
-- fixed-order sums, per contact and step): docs/performance.md compares boxes
-- of several sizes by it.
local pair_seconds = stage.contacts_s - stage.walls_s - stage.sums_s
io.stderr:write(string.format("threads' waits at the pair loop's barrier: %.3f thread-seconds\n", stage.pair_wait_s))
io.stderr:write(string.format("pair loop: %.1f ns per pair contact and step\n",
  1e9 * pair_seconds / math.max(1, p.steps * pair_contacts / math.max(samples, 1))))
io.stderr:write(string.format("pruned pair lists: the last step looked at %d pair candidates (all candidates, walls too: %d); %d prunes, %d list rebuilds so far\n",
  st.pair_candidates_visited, st.candidate_pairs, st.pair_list_prunes, st.list_rebuilds))
local line = {
  model = p.model, particles = st.particles, steps = p.steps, wall_s = wall,
  particle_steps_per_s = st.particles * p.steps / wall, mean_contacts = contacts / math.max(samples, 1),
  mean_pair_contacts = pair_contacts / math.max(samples, 1),
  mean_kinetic_energy = energy / math.max(samples, 1),
  list_rebuilds = st.list_rebuilds - st0.list_rebuilds, thread_rebalances = st.thread_rebalances - st0.thread_rebalances,
}
for k, v in pairs(stage) do line[k] = v end
print(bench.result_line(line))
if p.out ~= "" then
  sim:output { file = p.out, xdmf = false }
  sim:snapshot()
  sim:close()
end
