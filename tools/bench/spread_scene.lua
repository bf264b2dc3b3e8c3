-- The lattice box of tools/bench/distributed_scaling.cpp as a scene script,
-- for the cost of spreading a Lua scene over MPI ranks (tools/bench/spread_scene.sh):
-- a per_side^3 lattice of touching spheres (linear law with friction,
-- gravity, jostled by random velocities) in a box of six planes, stepped
-- `steps` times in one run, with the output's snapshot every `snapshot_every` steps and a
-- callback reading sim:stats() every `callback_every` steps (0: none). Prints
-- the final kinetic energy in hex (the same bits on any rank count).
local p = parameters {
  per_side = { default = 30, doc = "spheres along each side (per_side^3 in all)" },
  steps = { default = 400 },
  snapshot_every = { default = 0, doc = "steps between snapshots (0: none but the first and last)" },
  callback_every = { default = 0, doc = "steps between callbacks that read sim:stats() (0: none)" },
  canonical = { default = 1, doc = "1: canonical order (what a spread run uses)" },
}
local sim = simulation { dimension = 3 }
sim:material { name = "p", density = 2500 }
sim:material { name = "w", density = 0 }
local law = { model = "linear", k_normal = 2e3, restitution = 0.5, friction = 0.4 }
sim:contact { "p", "p", model = law.model, k_normal = law.k_normal, restitution = law.restitution, friction = law.friction }
sim:contact { "p", "w", model = law.model, k_normal = law.k_normal, restitution = law.restitution, friction = law.friction }
local n, r = p.per_side, 0.5e-3
local spacing = 1.98 * r
local extent = { n * spacing, n * spacing, 2 * n * spacing }
for axis = 1, 3 do
  local normal_lo, normal_hi, point_hi = { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 }
  normal_lo[axis], normal_hi[axis], point_hi[axis] = 1, -1, extent[axis]
  sim:wall_plane { name = "lo" .. axis, point = { -r, -r, -r }, normal = normal_lo, material = "w" }
  sim:wall_plane { name = "hi" .. axis, point = point_hi, normal = normal_hi, material = "w" }
end
local seed = 7
local function jostle()  -- a small linear congruential generator: the same on every rank
  seed = (seed * 1103515245 + 12345) % 2147483648
  return (seed / 2147483648 - 0.5) * 0.1
end
for a = 0, n - 1 do
  for b = 0, n - 1 do
    for c = 0, n - 1 do
      sim:add_particle { position = { a * spacing, b * spacing, c * spacing }, radius = r, material = "p",
                         velocity = { jostle(), jostle(), jostle() } }
    end
  end
end
sim:gravity { 0, 0, -9.81 }
if p.canonical == 1 then sim:set { canonical_order = true } end
sim:set { threads = 1 }
-- The output's own snapshots (by simulated time: every snapshot_every steps).
sim:output { snapshot_every = p.snapshot_every * sim:time_step() }
local readings = 0
if p.callback_every > 0 then
  sim:every { steps = p.callback_every, function(s) readings = readings + s:stats().kinetic_energy end }
end
sim:run { steps = p.steps }
local st = sim:stats()
print(string.format("spread_scene spheres=%d steps=%d kinetic_energy=%a readings=%a list_rebuilds=%d",
  n ^ 3, sim:step_count(), st.kinetic_energy, readings, st.list_rebuilds))
