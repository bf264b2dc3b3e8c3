-- A plane shear cell in 3D: beads between two rough walls (y = 0 and the
-- lid), periodic along the shearing direction x, smooth side walls in z.
-- The beads are placed loose; the lid is a servo that holds the normal
-- stress at `pressure` (its speed follows the stress error, as a
-- stress-controlled shear cell's lid does), and the walls slide past each
-- other at +-U/2. The scene reports the effective
-- friction coefficient mu_eff = |F_x| / |F_y| on the lid (the bulk friction of
-- the mu(I) rheology), the shear rate in the middle third of the gap against
-- U / gap (the rest is slip at the walls), and the inertial number
-- I = gamma_dot d / sqrt(P / rho).
--   build/granule run scenarios/shear_cell.lua
--   build/granule run scenarios/shear_cell.lua -D speed=0.2 -D friction=0.5 -o shear.h5
local granule = require "granule"
local p = parameters {
  particles = { default = 200, integer = true, min = 1, max = 1e6, doc = "number of beads" },
  radius = { default = 1e-3, above = 0, unit = "m", doc = "bead radius" },
  length = { default = 12e-3, above = 0, unit = "m", doc = "periodic length along x" },
  width = { default = 8e-3, above = 0, unit = "m", doc = "distance between the smooth side walls (z)" },
  pressure = { default = 1000, above = 0, unit = "Pa", doc = "normal stress the lid holds" },
  speed = { default = 0.1, above = 0, unit = "m/s", doc = "relative speed U of the walls" },
  friction = { default = 0.4, min = 0, doc = "bead-bead friction" },
  wall_friction = { default = 0.9, min = 0, doc = "bead-wall friction (rough walls drive the shear)" },
  duration = { default = 0.5, above = 0, unit = "s", doc = "time sheared" },
}
local sim = simulation { dimension = 3, periodic = { axis = "x", origin = 0, length = p.length } }
sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }
sim:material { name = "rough", density = 7800, young = 5e7, poisson = 0.3 }
sim:material { name = "smooth", density = 7800, young = 5e7, poisson = 0.3 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = p.friction }
sim:contact { "glass", "rough", model = "hertz_mindlin", restitution = 0.5, friction = p.wall_friction }
sim:contact { "glass", "smooth", model = "hertz_mindlin", restitution = 0.5, friction = 0 }
local bead_volume = p.particles * 4 / 3 * math.pi * p.radius ^ 3
-- Loose enough to place at random, and at least two diameters high (a few
-- beads make a layer thinner than one).
local fill_height = math.max(bead_volume / (0.2 * p.length * p.width), 4 * p.radius)
if not (p.length > 2 * p.radius and p.width > 2 * p.radius) then
  error(string.format("shear_cell: length=%g m and width=%g m must both exceed a bead's diameter (%g m)",
    p.length, p.width, 2 * p.radius))
end
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "rough" }
sim:wall_plane { name = "lid", point = { 0, fill_height, 0 }, normal = { 0, -1, 0 }, material = "rough" }
sim:wall_plane { name = "back", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "smooth" }
sim:wall_plane { name = "front", point = { 0, 0, p.width }, normal = { 0, 0, -1 }, material = "smooth" }
sim:fill { region = { box = { lo = { 0, 0, 0 }, hi = { p.length, fill_height, p.width } } }, count = p.particles,
           radius = p.radius, material = "glass", seed = 1, overlap = false }
local file = sim:output { snapshot_every = 0.05 }

-- The lid's servo: every 20 steps its normal speed is set from the stress
-- error, v = -(P - P_lid) A / (k_servo), capped at 0.2 m/s; k_servo is the
-- stiffness of a layer of beads under that load, so the lid settles within a
-- few of its oscillations without bouncing. P_lid is the mean over those 20
-- steps (sampled every 4th: each sample is a journaled call, kept in the
-- checkpoints), not the last step's force: a lid closing on the beads at constant
-- speed for 20 steps feels its largest force at the end of them, and where its
-- contacts come and go (low pressure, fast shear) a servo on that last force
-- held the mean stress well under `pressure` (63 Pa for 100 Pa).
local area = p.length * p.width
local lid_speed_x = 0
local servo_gain = 0.02 / (p.pressure * area)  -- m/s per N of stress error
local servo_samples, sample_every, force_sum, force_steps = 5, 4, 0, 0
-- The lid's force over the measuring window, summed at every servo sample: the
-- stress and mu_eff are time means over thousands of samples, not over the few
-- of the flow's snapshots, which the force's fluctuations from contact to
-- contact would leave scattered by tens of per cent.
local window = { from = math.huge, fx = 0, fy = 0, n = 0 }
local function servo(s)
  local lid_force = s:wall("lid").force
  if s:time() >= window.from then
    window.fx, window.fy, window.n = window.fx + lid_force[1], window.fy + lid_force[2], window.n + 1
  end
  force_sum, force_steps = force_sum + lid_force[2], force_steps + 1
  if force_steps < servo_samples then return end
  local stress = force_sum / force_steps / area  -- the beads push the lid up: force +y
  force_sum, force_steps = 0, 0
  local v = servo_gain * (stress - p.pressure) * area
  v = math.max(-0.2, math.min(0.2, v))
  s:set_wall("lid", { velocity = { lid_speed_x, v, 0 } })
end
sim:every { steps = sample_every, servo }
-- The lid starts at the loose fill's height and closes at 0.02 m/s while it
-- touches nothing: the stage allows that travel and half a second more.
-- Calm before the shear: the beads' kinetic energy (spins too) below that of all
-- of them moving at 3 % of the walls' relative speed to come, at any bead size.
local calm = granule.calm(sim, 0.03 * p.speed)
granule.stage(sim, { name = "compress", duration = fill_height / 0.02 + 0.5, check_every = 2000, stop_when = function(s)
  local stress = s:wall("lid").force[2] / area
  return math.abs(stress / p.pressure - 1) < 0.05 and calm(s)
end })

-- Shear: floor at -U/2, lid at +U/2 along x.
sim:set_wall("floor", { velocity = { -p.speed / 2, 0, 0 } })
lid_speed_x = p.speed / 2
local function gap_now(s) return s:wall("lid").point[2] end
local sums = { gap = 0, n = 0 }
-- The middle shear rate: the least-squares slope of v_x against y over the
-- beads in the middle third of the gap. A few layers hold few beads there,
-- so one sample's slope is noise (of either sign); the reported rate is one
-- fit through the beads of every sample in the measuring window.
local fit = { n = 0, sy = 0, sv = 0, syy = 0, syv = 0 }
local function middle_beads(s, into)
  local gap = gap_now(s)
  for _, id in ipairs(s:particles()) do
    local b = s:particle(id)
    local y = b.position[2]
    if y > gap / 3 and y < 2 * gap / 3 then
      into.n, into.sy, into.sv = into.n + 1, into.sy + y, into.sv + b.velocity[1]
      into.syy, into.syv = into.syy + y * y, into.syv + y * b.velocity[1]
    end
  end
  return into
end
local function slope(f)
  local spread = f.n * f.syy - f.sy * f.sy
  if f.n < 3 or not (spread > 0) then return nil end  -- too few beads, or all at one height
  return (f.n * f.syv - f.sy * f.sv) / spread
end
sim:series("shear", { "time", "lid_force_x", "lid_force_y", "gap", "middle_shear_rate" })
local started = sim:time()
window.from = started + 0.4 * p.duration  -- past the start-up of the flow
-- 50 samples of the flow over the run (every 0.01 s at the default duration),
-- 30 or 31 of them in the window (its start may fall on a sample), whatever the
-- duration a scene of another size needs.
local flow_every = p.duration / 50
sim:every { time = flow_every, function(s)
  local f = s:wall("lid").force
  local beads = middle_beads(s, { n = 0, sy = 0, sv = 0, syy = 0, syv = 0 })
  local rate = slope(beads)
  if not rate then return end
  s:append("shear", { s:time(), f[1], f[2], gap_now(s), rate })
  if s:time() >= window.from then
    sums.gap, sums.n = sums.gap + gap_now(s), sums.n + 1
    for k, v in pairs(beads) do fit[k] = fit[k] + v end
  end
end }
granule.stage(sim, { name = "shear", duration = p.duration })
assert(sums.n >= 3, string.format("too few samples of the sheared flow (%d; one every %g s after 40 %% " ..
  "of the run, with 3 beads or more in the middle third of the gap): raise particles (%d)",
  sums.n, flow_every, p.particles))

-- The values are reported as measured; what sheared beads should give
-- (mu_eff 0.05-1, a middle sheared in the walls' sense) is for tests to judge.
local gap = sums.gap / sums.n
local mu_eff = math.abs(window.fx / window.fy)
local rate = slope(fit)
local pressure = math.abs(window.fy / window.n) / area
local inertial = rate * 2 * p.radius / math.sqrt(pressure / 2500)
sim:result { mu_eff = mu_eff, middle_shear_rate = rate, nominal_shear_rate = p.speed / gap,
             pressure = pressure, inertial_number = inertial }
print(string.format("shear_cell: gap %.3g m, mu_eff %.3f, shear rate in the middle %.3g 1/s " ..
  "(U / gap %.3g 1/s), pressure %.3g Pa, inertial number %.3g (%d samples of the flow, %d of the lid's force)",
  gap, mu_eff, rate, p.speed / gap, pressure, inertial, sums.n, window.n))
print("results written to " .. file)
