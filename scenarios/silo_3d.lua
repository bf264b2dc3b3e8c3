-- A 3D silo discharge through a flat-bottomed orifice: a short version of the
-- OSBenchmark silo (Dosta et al. 2024): 4 mm glass-like spheres, damped
-- Hertz-Mindlin with friction, a finite tube closed by an annular disk whose
-- hole is the orifice. The bed is poured and settles on a shutter under the
-- hole; the shutter drops away, and the discharged mass is counted as the
-- particles fall below the outlet. The mass flow rate W over the steady
-- window (a least-squares line through the discharged mass) is compared with
-- Beverloo's law W = C rho_b sqrt(g) (D - k d)^2.5, C = 0.58, k = 1.5, rho_b
-- the settled bed's bulk density (docs/walls.md gives the study).
--   build/granule run scenarios/silo_3d.lua -D orifice=0.03
--   build/granule run scenarios/silo_3d.lua -D orifice=0.02 -D window_end=2.5
--   build/granule sweep scenarios/silo_3d.lua -D orifice=0.02,0.03 -D seed=1,2,3,4
local granule = require "granule"
local p = parameters {
  orifice = { default = 0.03, above = 0, unit = "m", doc = "orifice diameter D" },
  particles = { default = 6000, integer = true, min = 1, max = 1e7, doc = "number of spheres" },
  diameter = { default = 4e-3, above = 0, unit = "m", doc = "sphere diameter d" },
  silo_diameter = { default = 0.08, above = 0, unit = "m", doc = "silo (tube) diameter" },
  friction = { default = 0.5, min = 0, doc = "sphere-sphere and sphere-wall friction coefficient" },
  restitution = { default = 0.5, above = 0, max = 1, doc = "coefficient of restitution" },
  young = { default = 1e7, above = 0, unit = "Pa", doc = "Young's modulus (soft, for larger steps)" },
  settle = { default = 0.6, min = 0, unit = "s", doc = "time the poured bed settles on the shutter" },
  window_start = { default = 0.3, unit = "s", doc = "steady window start, after the opening" },
  window_end = { default = 1.2, unit = "s", doc = "steady window end, after the opening" },
  count_every = { default = 100, integer = true, min = 1, doc = "steps between counts of discharged spheres" },
  seed = { default = 1, integer = true, min = 0, doc = "the pour's random seed (an ensemble: several seeds)" },
}
-- The window is checked before the run: the discharge stage lasts until its end.
if not (p.window_start >= 0 and p.window_start < p.window_end) then
  error(string.format("window_start=%g s and window_end=%g s: need 0 <= window_start < window_end",
    p.window_start, p.window_end))
end
local d, D, Rs = p.diameter, p.orifice, p.silo_diameter / 2
assert(D > 2 * d and D < 2 * Rs, "orifice must lie between two sphere diameters and the silo's")
local density, g = 2500, 9.81
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = density, young = p.young, poisson = 0.3 }
sim:material { name = "steel", density = 7800, young = p.young, poisson = 0.3 }
for _, pair in ipairs { { "glass", "glass" }, { "glass", "steel" } } do
  sim:contact { pair[1], pair[2], model = "hertz_mindlin", restitution = p.restitution,
                friction = p.friction }
end
-- The bed's height at a solid fraction of 0.6, for the pour's region and the tube.
local bed = p.particles * (math.pi / 6 * d ^ 3) / 0.6 / (math.pi * Rs ^ 2)
-- The bulk density below is measured in a slab from one diameter above the
-- floor to 80 % of the bed's top: a bed too shallow leaves it empty.
local function bed_too_small(top, how)
  error(string.format("silo_3d: the bed (top %s %.3g m) is too small for the bulk-density slab, from one diameter "
    .. "(%.3g m) above the floor to 80 %% of the bed's top: raise particles (%g; at least about %d) or lower "
    .. "silo_diameter (%g m) or diameter", how, top, d, p.particles, math.ceil(1.25 * d / bed * p.particles),
    p.silo_diameter), 2)
end
if 0.8 * bed <= d then bed_too_small(bed, "expected at") end
sim:wall_cylinder { name = "silo", center = { 0, 0, 0 }, radius = Rs, bounds = { 0, 3 * bed },
                    material = "steel" }
sim:wall_disk { name = "bottom", center = { 0, 0, 0 }, normal = { 0, 0, 1 }, radius = Rs,
                inner_radius = D / 2, material = "steel" }
-- The shutter: a disk just under the orifice, which drops away at the opening.
sim:wall_disk { name = "shutter", center = { 0, 0, -0.25 * d }, normal = { 0, 0, 1 },
                radius = D / 2 + d, material = "steel" }
sim:fill { region = { cylinder = { center = { 0, 0, 0 }, radius = Rs, z_min = 0, z_max = 2.5 * bed } },
           count = p.particles, radius = d / 2, material = "glass", seed = p.seed, overlap = false }
sim:gravity { 0, 0, -g }
local file = sim:output { snapshot_every = 0.1 }
granule.stage(sim, { name = "pour and settle", duration = p.settle, check_every = 1000 })

-- The settled bed's bulk density: the spheres with centres in a slab from one
-- diameter above the floor to 80 % of the bed's top, over the slab's volume.
local top, mass_each = 0, 0
for _, id in ipairs(sim:particles()) do
  local b = sim:particle(id)
  top = math.max(top, b.position[3] + b.radius)
  mass_each = b.mass
end
local lo, hi, inside = d, 0.8 * top, 0
for _, id in ipairs(sim:particles()) do
  local z = sim:particle(id).position[3]
  if z > lo and z < hi then inside = inside + 1 end
end
if inside == 0 then bed_too_small(top, "at") end
local rho_b = inside * mass_each / (math.pi * Rs ^ 2 * (hi - lo))

-- Open: the shutter falls away and stops 25 diameters down (at the default
-- 4 mm spheres: at 2 m/s for 50 ms, 0.1 m), well below where the spheres are
-- counted and removed (4 diameters), so none lands on it. Its speed scales as
-- a free fall's over that drop (sqrt of the size), so that at any size it
-- leaves the outlet faster than the first spheres follow.
local size_ratio = d / 4e-3  -- to the declared default diameter
local shutter_speed, shutter_time = 2 * math.sqrt(size_ratio), 0.05 * math.sqrt(size_ratio)
local t_open = sim:time()
sim:set_wall("shutter", { velocity = { 0, 0, -shutter_speed } })
local discharged, times, masses = 0, {}, {}
local cut = -4 * d  -- below the outlet: counted and removed
sim:every { steps = p.count_every, name = "count discharged", function(s)
  if s:time() > t_open + shutter_time then s:set_wall("shutter", { velocity = { 0, 0, 0 } }) end
  for _, id in ipairs(s:particles()) do
    if s:particle(id).position[3] < cut then
      s:remove_particle(id)
      discharged = discharged + 1
    end
  end
  times[#times + 1] = s:time() - t_open
  masses[#masses + 1] = discharged * mass_each
end }
granule.stage(sim, { name = "discharge", duration = p.window_end, check_every = 1000 })

-- W: the least-squares slope of the discharged mass over a window.
local function slope(t0, t1)
  local n, st, sm, stt, stm = 0, 0, 0, 0, 0
  for k = 1, #times do
    local t = times[k]
    if t >= t0 and t <= t1 then
      n, st, sm = n + 1, st + t, sm + masses[k]
      stt, stm = stt + t * t, stm + t * masses[k]
    end
  end
  assert(n >= 3, "the window holds fewer than three counts")
  return (n * stm - st * sm) / (n * stt - st * st)
end
local W = slope(p.window_start, p.window_end)
assert(W > 0 and W < math.huge, "no discharge over the window")
-- Its steadiness: the slopes over the window's three thirds, their mean and
-- standard error (consecutive thirds of one run, so a guide, not an ensemble).
local thirds, third = {}, (p.window_end - p.window_start) / 3
for j = 0, 2 do thirds[j + 1] = slope(p.window_start + j * third, p.window_start + (j + 1) * third) end
local mean = (thirds[1] + thirds[2] + thirds[3]) / 3
local var = 0
for j = 1, 3 do var = var + (thirds[j] - mean) ^ 2 / 2 end
local se = math.sqrt(var / 3)
local C, k = 0.58, 1.5
local beverloo = C * rho_b * math.sqrt(g) * (D - k * d) ^ 2.5
sim:result { flow_rate = W, beverloo = beverloo, ratio = W / beverloo, bulk_density = rho_b,
             discharged = discharged, bed_top = top, flow_rate_thirds_mean = mean,
             flow_rate_thirds_se = se }
sim:series("discharge", { "time_after_opening", "discharged_mass" })
for k = 1, #times do sim:append("discharge", { times[k], masses[k] }) end
print(string.format("silo_3d: D = %.3g m, d = %.3g m, bed top %.4g m, bulk density %.1f kg/m^3, " ..
  "%d spheres discharged; W = %.4g kg/s over %.2f-%.2f s after opening; Beverloo %.4g kg/s; " ..
  "W / Beverloo = %.3f; thirds of the window %.4g, %.4g, %.4g kg/s (%.4g +- %.2g)", D, d, top, rho_b,
  discharged, W, p.window_start, p.window_end, beverloo, W / beverloo, thirds[1], thirds[2],
  thirds[3], mean, se))
print("results written to " .. file)
