-- A rotating drum in 3D: beads in a horizontal cylinder (axis z) between two
-- end plates, settled, then turned. In the rolling regime the free surface is
-- a plane tilted at the dynamic angle of repose; the scene fits that plane to
-- the top layer of beads (least squares over the beads highest in each slice
-- across the drum) and reports the angle, the Froude number omega^2 R / g and
-- the bed's mean kinetic energy.
--   build/granule run scenarios/drum_3d.lua
--   build/granule run scenarios/drum_3d.lua -D rpm=20 -D friction=0.5 -o drum.h5
--   build/granule run scenarios/drum_3d.lua -D drum=mesh -D facets=96   # the shell as a mesh
local granule = require "granule"
local p = parameters {
  rpm = { default = 30, unit = "1/min", doc = "drum speed" },
  particles = { default = 400, integer = true, min = 1, max = 1e6, doc = "number of beads (the random fill places up to about 30 % of the drum's volume)" },
  radius = { default = 1e-3, above = 0, unit = "m", doc = "bead radius" },
  drum_radius = { default = 15e-3, above = 0, unit = "m" },
  length = { default = 8e-3, above = 0, unit = "m", doc = "drum length along its axis" },
  friction = { default = 0.4, min = 0, doc = "bead-bead and bead-wall friction" },
  settle = { default = 0.5, min = 0, unit = "s", doc = "longest time allowed to settle" },
  duration = { default = 1.0, min = 0, unit = "s", doc = "time the drum turns" },
  drum = { default = "analytic", doc = "analytic (sim:wall_cylinder) | mesh (the shell as a triangle mesh)" },
  facets = { default = 96, integer = true, min = 3, max = 100000, doc = "mesh drum: flat facets around the shell" },
  flat_angle = { default = 20, unit = "deg", doc = "mesh drum: contacts closer in normal than this are one (sim:wall_mesh)" },
  seed = { default = 1, integer = true, doc = "seed of the random fill" },
}
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }
sim:material { name = "steel", density = 7800, young = 5e7, poisson = 0.3 }
for _, pair in ipairs { { "glass", "glass" }, { "glass", "steel" } } do
  sim:contact { pair[1], pair[2], model = "hertz_mindlin", restitution = 0.5, friction = p.friction }
end
if p.drum == "analytic" then
  sim:wall_cylinder { name = "drum", center = { 0, 0, 0 }, axis = { 0, 0, 1 }, radius = p.drum_radius,
                      inside = true, material = "steel" }
elseif p.drum == "mesh" then
  -- The shell as `facets` flat quads (two triangles each) whose corners lie on the
  -- circle: a polygon inscribed in it, reaching a bead radius past both end plates so
  -- that no bead meets the shell's open rims (granule.mesh_shapes writes it as an OBJ).
  local path = require("granule.mesh_shapes").prism {
    center = { 0, 0 }, radius = p.drum_radius, facets = p.facets, z_min = -p.radius, z_max = p.length + p.radius }
  sim:wall_mesh { name = "drum", file = path, material = "steel", axis = { 0, 0, 1 }, axis_point = { 0, 0, 0 },
                  flat_angle = p.flat_angle }
  os.remove(path)
else
  error("drum must be 'analytic' or 'mesh', got '" .. tostring(p.drum) .. "'")
end
sim:wall_plane { name = "back", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:wall_plane { name = "front", point = { 0, 0, p.length }, normal = { 0, 0, -1 }, material = "steel" }
sim:fill { region = { cylinder = { center = { 0, 0, 0 }, radius = p.drum_radius, z_min = 0, z_max = p.length } },
           count = p.particles, radius = p.radius, material = "glass", seed = p.seed, overlap = false }
sim:gravity { 0, -9.81, 0 }
local file = sim:output { snapshot_every = 0.05 }
granule.stage(sim, { name = "settle", duration = p.settle, check_every = 1000,
                     stop_when = function(s) return s:time() > 0.1 and s:stats().kinetic_energy < 1e-8 end })
-- Clockwise seen from +z (omega < 0): the surface rises on the left.
local omega = -granule.rpm(p.rpm)
local started = sim:time()
sim:set_wall("drum", { angular_velocity = omega })

-- The free surface's angle: the beads are binned in slices across the drum
-- (x); the highest bead centre of each slice is a point of the surface, and
-- a line through those of the middle half of the drum gives the slope.
local function surface_angle(s)
  local slices, width = 12, 2 * p.drum_radius / 12
  local highest = {}
  for _, id in ipairs(s:particles()) do
    local x = s:particle(id).position
    local k = math.floor((x[1] + p.drum_radius) / width)
    if not highest[k] or x[2] > highest[k][2] then highest[k] = { x[1], x[2] } end
  end
  local n, sx, sy, sxx, sxy = 0, 0, 0, 0, 0
  for k = slices // 4, slices - 1 - slices // 4 do
    local point = highest[k]
    if point then
      n, sx, sy = n + 1, sx + point[1], sy + point[2]
      sxx, sxy = sxx + point[1] ^ 2, sxy + point[1] * point[2]
    end
  end
  if n < 3 then return 0 / 0 end
  local slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
  return math.deg(math.atan(-slope))  -- rising to the left: a negative slope, a positive angle
end
local angles, energy, samples = {}, 0, 0
sim:series("surface", { "time", "angle" })
sim:every { time = 0.05, function(s)
  if s:time() > started + 0.3 * p.duration then  -- past the start-up of the flow
    local a = surface_angle(s)
    angles[#angles + 1] = a
    s:append("surface", { s:time(), a })
  end
  energy, samples = energy + s:stats().kinetic_energy, samples + 1
end }

granule.stage(sim, { name = "rotate", duration = p.duration })

local mean, spread = 0, 0
for _, a in ipairs(angles) do mean = mean + a / #angles end
for _, a in ipairs(angles) do spread = spread + (a - mean) ^ 2 / math.max(#angles - 1, 1) end
local froude = omega ^ 2 * p.drum_radius / 9.81
sim:result { repose_angle = mean, repose_angle_sd = math.sqrt(spread), froude = froude,
             mean_kinetic_energy = energy / math.max(samples, 1) }
print(string.format("drum_3d: Froude %.3g, dynamic angle of repose %.1f +- %.1f deg (%d samples), " ..
  "mean kinetic energy %.3g J", froude, mean, math.sqrt(spread), #angles, energy / math.max(samples, 1)))
assert(#angles >= 3, "too few samples of the free surface")
assert(mean > 5 and mean < 60, "the free surface of a rolling bed tilts by 5-60 degrees")
print("results written to " .. file)
