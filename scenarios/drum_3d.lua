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
-- The beads start inside the shell: the mesh's polygon reaches in to its
-- apothem R cos(pi / facets) between corners, and sim:fill keeps each whole
-- bead inside the region's circle, so that circle is the inscribed one.
local fill_radius = p.drum_radius
if p.drum == "mesh" then fill_radius = p.drum_radius * math.cos(math.pi / p.facets) end
if not (fill_radius > p.radius) then
  error(string.format("drum_3d: drum_radius=%g m with facets=%d leaves no room for a bead of radius=%g m",
    p.drum_radius, p.facets, p.radius))
end
local filled, why = pcall(sim.fill, sim, {
  region = { cylinder = { center = { 0, 0, 0 }, radius = fill_radius, z_min = 0, z_max = p.length } },
  count = p.particles, radius = p.radius, material = "glass", seed = p.seed, overlap = false })
if not filled then
  -- A stop (Ctrl-C, SIGTERM) during the fill is the stop, not a drum too small.
  if tostring(why):find("interrupted", 1, true) then error(why, 0) end
  error(string.format("drum_3d: particles=%d beads of radius=%g m do not fit a drum of drum_radius=%g m, " ..
    "length=%g m%s (%s)", p.particles, p.radius, p.drum_radius, p.length,
    p.drum == "mesh" and string.format(", facets=%d", p.facets) or "", tostring(why)))
end
sim:gravity { 0, -9.81, 0 }
local file = sim:output { snapshot_every = 0.05 }
-- Settled when the beads' kinetic energy (spins too) is below that of all of them
-- moving at 1.5 % of sqrt(g d), at any bead size (granule.calm).
local calm = granule.calm(sim, 0.015 * math.sqrt(9.81 * 2 * p.radius))
granule.stage(sim, { name = "settle", duration = p.settle, check_every = 1000,
                     stop_when = function(s) return s:time() > 0.1 and calm(s) end })
-- Clockwise seen from +z (omega < 0): the surface rises on the left.
local omega = -granule.rpm(p.rpm)
local started = sim:time()
sim:set_wall("drum", { angular_velocity = omega })

-- The free surface's angle: the beads are binned in slices across the drum
-- (x); the highest bead centre of each slice is a point of the surface, and
-- a line through those of the middle half of the drum gives the slope. The
-- angle is signed by the sense of turning, positive when the surface rises
-- where the wall comes up (on the left for rpm > 0). Fewer than three of
-- those slices holding a bead fit no line: nil.
local turning = p.rpm < 0 and -1 or 1
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
  if n < 3 then return nil end
  local slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
  return turning * math.deg(math.atan(-slope))  -- rising to the left: a negative slope, a positive angle
end

-- Beads whose centre is past the shell or an end plate have left the drum
-- (through a gap of the mesh, or started outside it); they would feed the
-- surface fit, so the run stops naming them. The mesh's polygon turns with
-- the drum: a centre at (rho, phi) is inside while rho cos(phi') <= R cos(pi / facets),
-- phi' its angle from the middle of the facet it faces.
local function escaped(s)
  local count, turned = 0, p.drum == "mesh" and s:wall("drum").angle or 0
  local sector, apothem = 2 * math.pi / p.facets, p.drum_radius * math.cos(math.pi / p.facets)
  for _, id in ipairs(s:particles()) do
    local x = s:particle(id).position
    local rho = math.sqrt(x[1] ^ 2 + x[2] ^ 2)
    local out = x[3] < 0 or x[3] > p.length
    if p.drum == "mesh" then
      local phi = (math.atan(x[2], x[1]) - turned) % sector
      out = out or rho * math.cos(phi - sector / 2) > apothem
    else
      out = out or rho > p.drum_radius
    end
    if out then count = count + 1 end
  end
  return count
end
local function check_escaped(s, when)
  local count = escaped(s)
  if count > 0 then
    error(string.format("drum_3d: %d of %d beads are outside the drum %s (drum=%s, facets=%d); " ..
      "the surface angle would count them", count, #s:particles(), when, p.drum, p.facets))
  end
end
check_escaped(sim, "after settling")

local angles, energy, samples, unfitted = {}, 0, 0, 0
sim:series("surface", { "time", "angle" })
sim:every { time = 0.05, function(s)
  if s:time() > started + 0.3 * p.duration then  -- past the start-up of the flow
    check_escaped(s, string.format("at t = %.3g s", s:time()))
    local a = surface_angle(s)
    if a then
      angles[#angles + 1] = a
      s:append("surface", { s:time(), a })
    else
      unfitted = unfitted + 1
    end
  end
  energy, samples = energy + s:stats().kinetic_energy, samples + 1
end }

granule.stage(sim, { name = "rotate", duration = p.duration })
check_escaped(sim, "at the end")

-- The angle is reported as measured: how steep a bed of these beads should
-- stand (5-60 deg rolling; about 0 without friction) is for tests to judge.
local froude = omega ^ 2 * p.drum_radius / 9.81
local mean_energy = energy / math.max(samples, 1)
if #angles == 0 then
  sim:result { froude = froude, mean_kinetic_energy = mean_energy }
  local why = unfitted > 0 and string.format("none of %d samples has beads in 3 of the middle slices: " ..
    "particles=%d too few to fit a surface", unfitted, p.particles) or
    string.format("no samples: duration=%g s too short, the surface is sampled every 0.05 s after 0.3 of it", p.duration)
  print(string.format("drum_3d: Froude %.3g, no angle of repose (%s), mean kinetic energy %.3g J",
    froude, why, mean_energy))
else
  local mean, spread = 0, 0
  for _, a in ipairs(angles) do mean = mean + a / #angles end
  for _, a in ipairs(angles) do spread = spread + (a - mean) ^ 2 / math.max(#angles - 1, 1) end
  sim:result { repose_angle = mean, repose_angle_sd = math.sqrt(spread), froude = froude,
               mean_kinetic_energy = mean_energy }
  print(string.format("drum_3d: Froude %.3g, dynamic angle of repose %.1f +- %.1f deg (%d samples%s), " ..
    "mean kinetic energy %.3g J", froude, mean, math.sqrt(spread), #angles,
    unfitted > 0 and string.format(", %d without a surface to fit", unfitted) or "", mean_energy))
end
print("results written to " .. file)
