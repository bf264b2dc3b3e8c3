-- The benchmark box's shaking floor (granule.bench) against its closed form,
-- z = A (1 - cos wt), v = A w sin wt: at rest at the bottom of its stroke at
-- t = 0, the phase of LAMMPS's `fix wall/gran ... wiggle` and of the LIGGGHTS
-- deck's `viblin ... phase pi` (tools/bench/). A state saved after whole periods
-- must restart in all three programs under a floor at rest; a floor starting at
-- mid-stroke (z = A sin wt) made LAMMPS's bed lift off and its contact work
-- drop (docs/performance.md). A sphere resting on the floor rides with it
-- (peak acceleration A w^2 = 0.5 g < g, so it never leaves).
local bench = require "granule.bench"
local amplitude, frequency, radius, density, k_normal = 5e-5, 50, 1e-3, 2500, 1e4
local sim = bench.shaken_box { per_side = 5, amplitude = amplitude, frequency = frequency, radius = radius,
                               density = density, k_normal = k_normal }
local omega = 2 * math.pi * frequency
local mass = 4 / 3 * math.pi * radius ^ 3 * density
local sag = mass * 9.81 / k_normal -- the resting overlap, m g / k_normal
local id = sim:add_particle { position = { 0.005, 0.005, radius - sag }, radius = radius, material = "glass" }

-- Floor: its integrated position may lag the closed form by O(A w dt) per
-- step's phase (1.5e-6 s of 0.02 s): 1e-3 A is ample and far below the
-- A (sin - (1 - cos)) ~ 0.4 A a mid-stroke start would leave at t = T/8.
-- Sphere: it follows the floor up to its overlap changing with the floor's
-- acceleration (at most 0.5 sag, 5e-9 m) and a weakly damped rattle in the
-- contact: 2 % of A.
local worst_floor, worst_sphere = 0, 0
local eighth = math.floor(1 / frequency / 8 / 1.5e-6 + 0.5)
for k = 1, 8 * 2 do
  sim:run { steps = eighth }
  local t = sim:time()
  local floor = sim:wall("floor")
  local z_floor = amplitude * (1 - math.cos(omega * t))
  worst_floor = math.max(worst_floor, math.abs(floor.point[3] - z_floor))
  local v_floor = amplitude * omega * math.sin(omega * t)
  assert(math.abs(floor.velocity[3] - v_floor) < 1e-3 * amplitude * omega,
    string.format("floor velocity %.6g at t = %.6g s, closed form %.6g", floor.velocity[3], t, v_floor))
  local z = sim:particle(id).position[3]
  worst_sphere = math.max(worst_sphere, math.abs(z - (radius - sag + z_floor)))
end
assert(worst_floor < 1e-3 * amplitude, string.format("floor off z = A (1 - cos wt) by %.3g m", worst_floor))
assert(worst_sphere < 0.02 * amplitude, string.format("sphere off the floor's stroke by %.3g m", worst_sphere))
print(string.format("bench_floor ok: floor within %.2g m, sphere within %.2g m of the closed form", worst_floor,
  worst_sphere))
