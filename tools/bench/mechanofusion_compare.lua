-- The 2D Mechanofusion base case (Table 4.1) for side-by-side timing against
-- LAMMPS (tools/bench/compare.py). Without `state`, it settles the system for
-- `settle` seconds and saves the state (the timed runs of both programs start
-- from it); with `state`, it loads that snapshot and times `steps` steps.
--   build/granule run tools/bench/mechanofusion_compare.lua -D settle=0.05 -D save=mf_state.h5
--   build/granule run tools/bench/mechanofusion_compare.lua -D state=mf_state.h5 -D steps=20000 --threads 2
-- The timed run prints the stage times on stderr and one line on stdout for
-- compare.py (bench.result_line: wall and stage seconds, mean contacts).
local granule = require "granule"
local bench = require "granule.bench"
-- A binary built elsewhere loads its own tree's library: say so, not "nil".
assert(bench.result_line, "granule.bench lacks result_line (an older lua/): set GRANULE_LUA_PATH to this tree's lua/")
local p = parameters {
  model = { default = "linear", doc = "linear (the law LAMMPS has too) | walton_braun | hertz_mindlin | thornton_elastic" },
  particles = { default = 1500 },
  settle = { default = 0.05, unit = "s", doc = "settling time when preparing" },
  save = { default = "", doc = "write the settled state here (HDF5 snapshot) and stop" },
  state = { default = "", doc = "start from this snapshot and time the run" },
  steps = { default = 20000 },
  time_step = { default = 6.6936e-8, unit = "s", doc = "Eq. 4.1 for Table 4.1; the same in both programs" },
  rpm = { default = 2000 },
  k_normal = { default = 2e4, unit = "N/m" },
  restitution = { default = 0.85 },
  young = { default = 5e8, unit = "Pa", doc = "Young's modulus of both materials, for the Hertz laws" },
  poisson = { default = 0.3, doc = "Poisson's ratio of both materials, for the Hertz laws" },
}
local sim = simulation { dimension = 2, time_step = p.time_step }
-- The Hertz laws read the materials' elastic constants; the others do not.
local elastic = (p.model == "hertz_mindlin" or p.model == "thornton_elastic") and { p.young, p.poisson } or {}
sim:material { name = "powder", density = 1200, young = elastic[1], poisson = elastic[2] }
sim:material { name = "steel", density = 7800, young = elastic[1], poisson = elastic[2] }
local function law(mu)
  if p.model == "linear" then
    return { model = "linear", k_normal = p.k_normal, restitution = p.restitution, friction = mu }
  elseif p.model == "walton_braun" then
    return { model = "walton_braun", k_load = p.k_normal, restitution = p.restitution, friction = mu }
  elseif p.model == "hertz_mindlin" then
    return { model = "hertz_mindlin", restitution = p.restitution, friction = mu }
  elseif p.model == "thornton_elastic" then  -- elastic: no damping
    return { model = "thornton_elastic", friction = mu }
  end
  error("model: unknown '" .. p.model .. "' (linear, walton_braun, hertz_mindlin, thornton_elastic)")
end
local pp, pw = law(0.4), law(0.5)
pp[1], pp[2], pw[1], pw[2] = "powder", "powder", "powder", "steel"
sim:contact(pp)
sim:contact(pw)
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 12.5e-3, angular_velocity = granule.rpm(p.rpm), material = "steel" }
sim:wall_cylinder { name = "inner", center = { 5.9e-3, 0 }, radius = 5e-3, inside = false, material = "steel" }
if p.state == "" then
  sim:fill { region = { circle = { center = { 0, 0 }, radius = 12.5e-3 } }, count = p.particles, radius = 0.2e-3,
             material = "powder", seed = 1, max_speed = 0.01 }
  sim:run { duration = p.settle }
  assert(p.save ~= "", "give -D save=FILE to keep the settled state")
  sim:output { file = p.save, xdmf = false }
  sim:snapshot()
  sim:close()
  print("settled state written to " .. p.save)
  return
end
sim:load_particles { file = p.state }
local contacts, pair_contacts, energy, visited, samples = 0, 0, 0, 0, 0
sim:every { steps = 100, function(s)
  local st = s:stats()
  contacts, pair_contacts = contacts + st.contacts_particle + st.contacts_wall, pair_contacts + st.contacts_particle
  visited = visited + st.pair_candidates_visited  -- the pruned lists at work (docs/performance.md)
  energy = energy + st.kinetic_energy_translational  -- as LAMMPS's `ke`, for checking the flows agree
  samples = samples + 1
end }
sim:run { steps = 1 }  -- lists built, first contacts formed: not part of the timing
local t0, tm0, st0 = wall_time(), sim:timings(), sim:stats()
sim:run { steps = p.steps }
local wall = wall_time() - t0
local stage = bench.stage_seconds(sim, tm0)
local st = sim:stats()
io.stderr:write(string.format("stages [s]: neighbour %.3f contacts %.3f (of which fixed-order sums %.3f) diagnostics %.3f integrate %.3f hooks %.3f; thread rebalances %d, list rebuilds %d\n",
  stage.neighbour_s, stage.contacts_s, stage.sums_s, stage.diagnostics_s, stage.integrate_s, stage.hooks_s,
  st.thread_rebalances, st.list_rebuilds))
local line = {
  model = p.model, particles = st.particles, steps = p.steps, wall_s = wall,
  particle_steps_per_s = st.particles * p.steps / wall, mean_contacts = contacts / math.max(samples, 1),
  mean_pair_contacts = pair_contacts / math.max(samples, 1),
  mean_kinetic_energy = energy / math.max(samples, 1),
  mean_candidates_visited = visited / math.max(samples, 1),
  list_rebuilds = st.list_rebuilds - st0.list_rebuilds, thread_rebalances = st.thread_rebalances - st0.thread_rebalances,
  list_prunes = st.pair_list_prunes - st0.pair_list_prunes,
}
for k, v in pairs(stage) do line[k] = v end
print(bench.result_line(line))
