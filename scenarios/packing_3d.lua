-- A 3D packing under gravity, the first scene of most DEM codes: glass beads
-- poured into a square box settle on its floor. It checks what a settled bed
-- must satisfy and reports the bed's solid fraction: the floor and the side
-- walls together carry the weight (the side walls take a share by friction,
-- of either sign as the bed last moved against them), and frictional spheres
-- in a narrow box settle looser than random close packing
-- (0.64), toward random loose packing (0.55-0.60).
--   build/granule run scenarios/packing_3d.lua
--   build/granule run scenarios/packing_3d.lua -D particles=4000 -D friction=0.1 -o packing.h5
--   build/granule run scenarios/packing_3d.lua -D twisting_friction=0.1   # beads that cannot spin freely
--                                                                           # about their contact normals
local granule = require "granule"
local p = parameters {
  particles = { default = 800, integer = true, min = 1, max = 1e6, doc = "number of beads" },
  radius = { default = 1e-3, above = 0, unit = "m", doc = "bead radius" },
  box = { default = 16e-3, above = 0, unit = "m", doc = "side of the square box" },
  friction = { default = 0.3, min = 0, doc = "bead-bead and bead-wall friction coefficient" },
  restitution = { default = 0.5, above = 0, max = 1, doc = "coefficient of restitution (damped Hertz-Mindlin)" },
  settle = { default = 1.0, min = 0, unit = "s", doc = "longest time allowed to settle" },
  rolling_friction = { default = 0, min = 0, doc = "rolling friction coefficient mu_r (epsd; 0: none)" },
  twisting_friction = { default = 0, min = 0,
                        doc = "twisting friction coefficient mu_t (epsd; 0: beads spin about the vertical freely)" },
  rolling_damping = { default = 0.3, min = 0,
                      doc = "damping ratio of the rolling and twisting springs (used where either friction > 0)" },
  seed = { default = 1, integer = true, min = 1, doc = "seed of the pour's positions" },
}
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }  -- a soft glass: larger steps
sim:material { name = "steel", density = 7800, young = 5e7, poisson = 0.3 }
for _, pair in ipairs { { "glass", "glass" }, { "glass", "steel" } } do
  -- Both resistances 0 (the default) is the plain law.
  sim:contact { pair[1], pair[2], model = "hertz_mindlin", restitution = p.restitution,
                friction = p.friction, rolling_friction = p.rolling_friction,
                twisting_friction = p.twisting_friction, rolling_damping = p.rolling_damping }
end
local half = p.box / 2
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "steel" }
-- In a fixed order (a list, not pairs over names): the walls' order is their
-- contacts' order, and with it the order of the sums, so the run repeats bit for bit.
for _, wall in ipairs { { "west", { -half, 0, 0 }, { 1, 0, 0 } }, { "east", { half, 0, 0 }, { -1, 0, 0 } },
                        { "south", { 0, 0, -half }, { 0, 0, 1 } }, { "north", { 0, 0, half }, { 0, 0, -1 } } } do
  sim:wall_plane { name = wall[1], point = wall[2], normal = wall[3], material = "steel" }
end
-- A loose cloud four times the bed's height, without overlaps, and at least
-- two diameters high (a few beads make a bed thinner than one).
if not (p.box > 2 * p.radius) then
  error(string.format("packing_3d: box=%g m must be wider than a bead (2 radius = %g m)", p.box, 2 * p.radius))
end
local height = math.max(4 * p.particles * (4 / 3 * math.pi * p.radius ^ 3) / 0.6 / p.box ^ 2, 4 * p.radius)
sim:fill { region = { box = { lo = { -half, 0, -half }, hi = { half, height, half } } }, count = p.particles,
           radius = p.radius, material = "glass", seed = p.seed, overlap = false }
sim:gravity { 0, -9.81, 0 }
local file = sim:output { snapshot_every = 0.05 }
-- Settled when the beads' kinetic energy (spins too) is below that of all of them
-- moving at 0.35 % of sqrt(g d), at any bead size (granule.calm), at three checks
-- in a row: a tall column rings as a whole, passing near rest twice a period.
local calm = granule.calm(sim, 0.0035 * math.sqrt(9.81 * 2 * p.radius), 3)
local settle = granule.stage(sim, { name = "settle", duration = p.settle, check_every = 1000,
                                   stop_when = function(s) return s:time() > 0.2 and calm(s) end })

-- The bed: weight against the walls' forces, and the solid fraction below the
-- top layer (the volume of the beads whose centres lie in the lower 80 % of
-- the bed over that slab's volume).
local weight, top, beads = 0, 0, {}
for _, id in ipairs(sim:particles()) do
  local b = sim:particle(id)
  weight = weight + b.mass * 9.81
  top = math.max(top, b.position[2] + b.radius)
  beads[#beads + 1] = b
end
local slab = 0.8 * top
local volume = 0
for _, b in ipairs(beads) do
  if b.position[2] < slab then volume = volume + 4 / 3 * math.pi * b.radius ^ 3 end
end
local solid_fraction = volume / (p.box ^ 2 * slab)
-- The walls' forces as time means over 7 sqrt(d / g) after settling: what is
-- left of a column's ringing swings one step's forces by several per cent about
-- the weight. sqrt(d / g), a bead's fall over its own size, is the scene's time
-- scale, so the window holds the same at any bead size; over 7 of them (0.1 s
-- at the default beads) the ringing column of params.packing_3d_ringing_column
-- averages to the weight within 0.5 %.
-- (A bed that did not settle is reported as it stands, and refused below.)
local floor, sides, samples = 0, 0, 0
local function add_forces(s)
  floor = floor + s:wall("floor").force[2]
  for _, name in ipairs { "west", "east", "south", "north" } do sides = sides + s:wall(name).force[2] end
  samples = samples + 1
end
if settle.stopped then
  local forces = sim:every { steps = 10, name = "wall forces", add_forces }
  granule.stage(sim, { name = "measure", duration = 7 * math.sqrt(2 * p.radius / 9.81) })
  sim:remove_hook(forces)
else
  add_forces(sim)
end
floor, sides = floor / samples, sides / samples
local stats = sim:stats()
local ke = stats.kinetic_energy
local settled = settle.stopped and true or false
-- settle_time: when the bed was judged calm (the end of `settle`); the
-- rotational share of what kinetic energy is left after the measurement.
sim:result { solid_fraction = solid_fraction, bed_height = top, floor_share = -floor / weight,
             wall_share = -sides / weight, kinetic_energy = ke, settled = settled and 1 or 0,
             settle_time = settle.time,
             rotational_share = ke > 0 and stats.kinetic_energy_rotational / ke or 0 }
print(string.format("packing_3d: t = %.3f s, bed height %.4g m, solid fraction %.3f, floor carries %.1f %% " ..
  "and the side walls %.1f %% of the weight, kinetic energy %.2g J (rotational share %.4f)",
  sim:time(), top, solid_fraction, -100 * floor / weight, -100 * sides / weight, ke,
  ke > 0 and stats.kinetic_energy_rotational / ke or 0))
-- A bed still moving when `settle` ran out is no packing, and its walls need not
-- carry its weight yet: said so, rather than blamed on the walls.
if not settled and not settle.interrupted then
  error(string.format("packing_3d: the bed did not settle within settle=%g s (kinetic energy %.3g J " ..
    "at t = %.3f s; it is judged from t = 0.2 s, and larger beads fall longer): raise settle",
    p.settle, ke, sim:time()), 0)
end
assert(math.abs(-(floor + sides) / weight - 1) < 0.02, "the walls do not carry the bed's weight")
-- The solid fraction is reported as measured (a bed of a few beads is no
-- packing); that a bed of hundreds lies between random loose and close
-- packing is for tests to judge.
print("results written to " .. file)
