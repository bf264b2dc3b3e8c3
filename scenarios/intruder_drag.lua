-- Slow drag of an intruder through a granular bed (after Albert et al., Phys.
-- Rev. Lett. 82, 205 (1999), who dragged a rod; here a sphere): glass beads
-- settle under gravity in a box periodic along x, around a fixed sphere of
-- diameter D held at a height; then the sphere is dragged along x at a set
-- speed (prescribed motion: a fixed particle given a velocity moves at it
-- whatever touches it, docs/walls.md) and the force the beads exert on it is
-- the drag. In the slow, quasi-static regime the drag grows with the
-- hydrostatic pressure at the intruder's depth h and with its cross-section,
-- F = k rho_bulk g h D^2, independent of the speed (Albert et al.'s rod: F
-- proportional to rho g h^2 times its width); the scene reports the mean drag
-- over the steady part of the drag with its standard error (block means), the
-- depth h it measured and k, so that a sweep over depth or speed tests both
-- claims:
--   build/granule run scenarios/intruder_drag.lua
--   build/granule sweep scenarios/intruder_drag.lua -D height=8e-3,14e-3,20e-3 -o drag
local granule = require "granule"
local p = parameters {
  particles = { default = 3000, integer = true, min = 10, max = 1e6, doc = "number of beads" },
  radius = { default = 1e-3, above = 0, unit = "m", doc = "mean bead radius (beads 0.9-1.1 of it)" },
  intruder_radius = { default = 3e-3, above = 0, unit = "m", doc = "radius of the dragged sphere" },
  height = { default = 12e-3, above = 0, unit = "m", doc = "height of the intruder's centre above the floor" },
  length = { default = 40e-3, above = 0, unit = "m", doc = "periodic length along x (the drag direction)" },
  width = { default = 20e-3, above = 0, unit = "m", doc = "distance between the side walls (y)" },
  speed = { default = 0.05, above = 0, unit = "m/s", doc = "drag speed" },
  travel = { default = 40e-3, above = 0, unit = "m", doc = "distance dragged (the drag is averaged over its last 3/4)" },
  friction = { default = 0.4, min = 0, doc = "bead-bead and bead-intruder friction" },
  seed = { default = 1, integer = true, min = 1, doc = "seed of the beads' placement" },
}
local R = p.intruder_radius
if not (p.width > 2 * R + 4 * p.radius and p.length > 2 * R + 4 * p.radius) then
  error(string.format("intruder_drag: length=%g m and width=%g m must exceed the intruder's diameter "
    .. "(%g m) by two bead diameters", p.length, p.width, 2 * R))
end
if not (p.height > R) then
  error(string.format("intruder_drag: height=%g m must exceed intruder_radius=%g m (its centre "
    .. "above the floor)", p.height, R))
end
local density = 2500
local sim = simulation { dimension = 3, periodic = { axis = "x", origin = 0, length = p.length } }
sim:material { name = "glass", density = density, young = 5e7, poisson = 0.25 }
sim:material { name = "steel", density = 7800, young = 5e7, poisson = 0.3 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = p.friction }
sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.5, friction = p.friction }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:wall_plane { name = "left", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "steel" }
sim:wall_plane { name = "right", point = { 0, p.width, 0 }, normal = { 0, -1, 0 }, material = "steel" }
sim:gravity { 0, 0, -9.81 }
-- The intruder first (fixed, at rest), then the beads around it: the fill keeps clear of it.
local intruder = sim:add_particle { position = { p.length / 2, p.width / 2, p.height }, radius = R,
                                    material = "steel", fixed = true }
local bead_volume = p.particles * 4 / 3 * math.pi * p.radius ^ 3
local fill_height = bead_volume / (0.3 * p.length * p.width) + p.height + R
sim:fill { region = { box = { lo = { 0, 0, 0 }, hi = { p.length, p.width, fill_height } } },
           count = p.particles, radius_min = 0.9 * p.radius, radius_max = 1.1 * p.radius,
           material = "glass", seed = p.seed, overlap = false }
-- The box's length against the engine's rule for a periodic axis (more than twice
-- the largest contact reach), said in the scene's terms before anything runs.
local ok, why = pcall(function() sim:prepare() end)
if not ok then
  error(string.format("intruder_drag: length=%g m is too short for intruder_radius=%g m: %s",
    p.length, R, tostring(why)), 0)
end
-- Settle: the beads rain down around the intruder and come to rest (their kinetic
-- energy below that of all of them moving at 1 % of sqrt(g d), three checks in a
-- row: the same rest whatever the drag speed, so that a sweep over speed compares
-- beds settled alike).
local calm = granule.calm(sim, 0.01 * math.sqrt(9.81 * 2 * p.radius), 3)
sim:output { snapshot_every = math.max(p.travel / p.speed / 20, 0.01) }
granule.stage(sim, { name = "settle", duration = 2 * math.sqrt(2 * fill_height / 9.81) + 1,
                     check_every = 2000, stop_when = calm })

-- The bed's surface: the mean top of the beads in the highest layer (those whose
-- top is within a bead diameter of the highest top), away from the intruder's wake.
local function surface(s)
  local top, tops = -math.huge, {}
  for _, id in ipairs(s:particles()) do
    local b = s:particle(id)
    if not b.fixed then
      local z = b.position[3] + b.radius
      tops[#tops + 1] = z
      if z > top then top = z end
    end
  end
  local sum, n = 0, 0
  for _, z in ipairs(tops) do
    if z > top - 2 * p.radius then sum, n = sum + z, n + 1 end
  end
  return sum / n
end
local depth = surface(sim) - p.height
if not (depth > R) then
  error(string.format("intruder_drag: the settled bed's surface (%.4g m) is not above the intruder's "
    .. "top (%.4g m): raise particles (%d) or lower height", depth + p.height, p.height + R, p.particles))
end

-- Drag: the intruder moves at `speed` along x whatever the beads do; the force
-- they exert on it is read every few steps.
sim:set_velocity(intruder, { p.speed, 0, 0 })
sim:series("drag", { "time", "travel", "drag", "lift" })
local start = sim:time()
local duration = p.travel / p.speed
local window_from = start + 0.25 * duration
local blocks, block, sampled = {}, { sum = 0, n = 0 }, 0
local block_time = 0.75 * duration / 10  -- ten block means over the window
local next_block = window_from + block_time
sim:every { steps = 10, function(s)
  local f = s:particle(intruder).force
  local t = s:time()
  if t >= window_from then
    block.sum, block.n = block.sum + (-f[1]), block.n + 1
    sampled = sampled + 1
    if t >= next_block then
      blocks[#blocks + 1] = block.sum / block.n
      block, next_block = { sum = 0, n = 0 }, next_block + block_time
    end
  end
end }
sim:every { time = duration / 200, function(s)
  local f = s:particle(intruder).force
  s:append("drag", { s:time(), (s:time() - start) * p.speed, -f[1], f[3] })
end }
granule.stage(sim, { name = "drag", duration = duration })
if block.n > 0 then blocks[#blocks + 1] = block.sum / block.n end
assert(#blocks >= 3, "intruder_drag: too few samples of the drag (" .. sampled .. "): lengthen travel")

local mean, n = 0, #blocks
for _, b in ipairs(blocks) do mean = mean + b end
mean = mean / n
local var = 0
for _, b in ipairs(blocks) do var = var + (b - mean) ^ 2 end
local standard_error = math.sqrt(var / (n - 1) / n)
-- The bulk density of the settled bed below its surface (beads' mass over the
-- box's volume up to the surface, the intruder's volume left out).
local bead_mass = 0
for _, id in ipairs(sim:particles()) do
  local b = sim:particle(id)
  if not b.fixed then bead_mass = bead_mass + b.mass end
end
local bulk = bead_mass / (p.length * p.width * (depth + p.height) - 4 / 3 * math.pi * R ^ 3)
local D = 2 * R
local k = mean / (bulk * 9.81 * depth * D * D)
sim:result { depth = depth, drag = mean, drag_standard_error = standard_error, bulk_density = bulk, k = k }
print(string.format("intruder_drag: depth %.4g m (D = %.3g m, speed %.3g m/s), drag %.4g +- %.2g N "
  .. "(%d block means), bulk density %.4g kg/m^3, k = F / (rho_bulk g h D^2) = %.3g",
  depth, D, p.speed, mean, standard_error, n, bulk, k))
