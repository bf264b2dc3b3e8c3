-- A conical hopper read from an STL file: spheres settle in it on a gate
-- closing the outlet, then the gate drops away and they discharge. The
-- hopper is a mesh wall (docs/mesh_walls.md); its outlet, where the cone
-- meets the gate, and the cone's seam with the bin are concave edges.
-- The scene reports the mass discharged per second while the hopper drains.
--   /usr/bin/python3 tools/make_hopper_stl.py -o hopper.stl
--   build/granule run scenarios/hopper_mesh.lua -D file=hopper.stl -o hopper.h5
-- The geometry parameters must be those the file was made with (the tool's
-- defaults are this scene's).
local granule = require "granule"
local p = parameters {
  file = { default = "hopper.stl", doc = "the hopper (tools/make_hopper_stl.py), in metres" },
  bin_radius = { default = 0.03, above = 0, unit = "m" },
  bin_height = { default = 0.04, above = 0, unit = "m" },
  outlet_radius = { default = 0.008, above = 0, unit = "m" },
  half_angle = { default = 30, above = 0, below = 90, unit = "deg", doc = "the cone's, from the axis" },
  particles = { default = 1500 , integer = true, min = 1, max = 1e6},
  radius = { default = 1.5e-3, above = 0, unit = "m", doc = "sphere radius" },
  friction = { default = 0.4 , min = 0},
  settle = { default = 0.3, min = 0, unit = "s", doc = "longest time allowed to settle on the gate" },
  duration = { default = 1.0, min = 0, unit = "s", doc = "time allowed to discharge" },
}
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }
sim:material { name = "steel", density = 7800, young = 5e7, poisson = 0.3 }
for _, pair in ipairs { { "glass", "glass" }, { "glass", "steel" } } do
  sim:contact { pair[1], pair[2], model = "hertz_mindlin", restitution = 0.5, friction = p.friction }
end
local cone_height = (p.bin_radius - p.outlet_radius) / math.tan(math.rad(p.half_angle))
sim:wall_mesh { name = "hopper", file = p.file, material = "steel" }
-- The parameters place the fill and the gate; the file is the hopper. Every
-- vertex must lie on the surface they describe (radius outlet_radius + z
-- tan(half_angle) up the cone, bin_radius up the bin, z from 0 to the bin's
-- top), within 0.1 % of bin_radius (an STL stores single precision), else the
-- beads would be filled through the wall or beside it.
do
  local top = cone_height + p.bin_height
  local tolerance = 1e-3 * p.bin_radius
  local worst, at = 0, nil
  local z_low, z_high = math.huge, -math.huge
  for _, v in ipairs(require("granule.mesh_shapes").vertices(p.file)) do
    local z = v[3]
    z_low, z_high = math.min(z_low, z), math.max(z_high, z)
    local expected = z < cone_height and p.outlet_radius + z * math.tan(math.rad(p.half_angle)) or p.bin_radius
    local off = math.abs(math.sqrt(v[1] ^ 2 + v[2] ^ 2) - expected)
    if off > worst then worst, at = off, v end
  end
  if worst > tolerance or math.abs(z_low) > tolerance or math.abs(z_high - top) > tolerance then
    error(string.format("hopper_mesh: file '%s' is not the hopper of bin_radius=%g m, bin_height=%g m, " ..
      "outlet_radius=%g m, half_angle=%g deg (outlet at z = 0, top at z = %.4g m): its vertices span z = %.4g to " ..
      "%.4g m, and the one at (%.4g, %.4g, %.4g) lies %.3g m off that surface; give the parameters the file " ..
      "was made with (tools/make_hopper_stl.py)", p.file, p.bin_radius, p.bin_height, p.outlet_radius,
      p.half_angle, top, z_low, z_high, at and at[1] or 0, at and at[2] or 0, at and at[3] or 0, worst))
  end
end
sim:wall_plane { name = "gate", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:fill { region = { cylinder = { center = { 0, 0, 0 }, radius = p.bin_radius - p.radius,
                                   z_min = cone_height, z_max = cone_height + p.bin_height } },
           count = p.particles, radius = p.radius, material = "glass", seed = 1, overlap = false }
sim:gravity { 0, 0, -9.81 }
sim:output { snapshot_every = 0.05 }

-- Settled when the spheres' kinetic energy (spins too) is below that of all of them
-- moving at 1.1 % of sqrt(g d), at any size (granule.calm).
local calm = granule.calm(sim, 0.011 * math.sqrt(9.81 * 2 * p.radius))
granule.stage(sim, { name = "settle", duration = p.settle, check_every = 500,
                     stop_when = function(s) return s:time() > 0.1 and calm(s) end })

-- The gate drops away; a sphere that fell 2 cm below the outlet has left and
-- is removed.
local mass = sim:particle(sim:particles()[1]).mass
sim:set_wall("gate", { velocity = { 0, 0, -2 } })
local opened, discharged = sim:time(), 0
local times = {}
sim:series("discharge", { "time", "discharged" })
sim:every { steps = 200, function(s)
  for _, id in ipairs(s:particles()) do
    if s:particle(id).position[3] < -0.02 then
      s:remove_particle(id)
      discharged = discharged + 1
      times[#times + 1] = s:time() - opened
    end
  end
  s:append("discharge", { s:time(), discharged })
end }
granule.stage(sim, { name = "discharge", duration = p.duration, check_every = 1000,
                     stop_when = function(s) return #s:particles() == 0 end })

-- The rate while the hopper drains steadily: between the 20th and the 80th
-- percentile of the exit times.
local rate = 0
if #times >= 10 then
  local a, b = times[math.floor(0.2 * #times)], times[math.floor(0.8 * #times)]
  if b > a then rate = (math.floor(0.8 * #times) - math.floor(0.2 * #times)) * mass / (b - a) end
end
print(string.format("hopper: %d of %d spheres discharged in %.3g s; rate %.4g kg/s; force on the hopper %.4g N",
  discharged, p.particles, sim:time() - opened, rate, sim:wall("hopper").force[3]))
sim:result { discharged = discharged, rate = rate }
