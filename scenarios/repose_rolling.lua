-- A pile's angle of repose against rolling resistance (2D): spheres fill a
-- column against a left wall, on a floor; the gate on the right is pulled
-- away and the column collapses into a pile. The angle is the slope of a
-- line fitted to the pile's surface (the highest particle in each bin of
-- width 2 r_max), between 15 % and 85 % of its run-out. Rolling friction
-- resists the rolling that lets the spheres run out: the angle rises with
-- mu_r (docs/contact_models.md, "Rolling resistance").
--
--   build/granule run scenarios/repose_rolling.lua -D rolling_friction=0.2 -D seed=1
--   tools/repose_study.sh      (the figure docs/figures/repose_rolling.png)
local granule = require "granule"

local p = parameters {
  rolling_friction = { default = 0.1, min = 0, doc = "mu_r of every pair (0: none)" },
  rolling_model = { default = "epsd", doc = "epsd | constant" },
  particles = { default = 200, integer = true, min = 1, max = 1e6, doc = "number of spheres" },
  radius_min = { default = 0.8e-3, min = 1e-9, unit = "m" },
  radius_max = { default = 1.2e-3, min = 1e-9, unit = "m" },
  width = { default = 20e-3, above = 0, unit = "m", doc = "column width" },
  seed = { default = 1, integer = true, doc = "seed of the fill" },
  duration = { default = 1.5, above = 0, unit = "s", doc = "longest time allowed to collapse and settle" },
}

local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
local function law(mu)
  local l = { model = "linear", k_normal = 2e3, restitution = 0.5, friction = mu }
  if p.rolling_friction > 0 then
    l.rolling_friction, l.rolling_model = p.rolling_friction, p.rolling_model
    if p.rolling_model == "epsd" then l.rolling_damping = 0.3 end  -- the constant torque has no dashpot
  end
  return l
end
local gg, gs = law(0.5), law(0.5)
gg[1], gg[2], gs[1], gs[2] = "glass", "glass", "glass", "steel"
sim:contact(gg)
sim:contact(gs)

local height = 4 * p.width
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:wall_plane { name = "back", point = { 0, 0 }, normal = { 1, 0 }, material = "steel" }
sim:wall_plane { name = "gate", point = { p.width, 0 }, normal = { -1, 0 }, material = "steel" }
-- Not overlapping: an overlapping start throws spheres about the column (the
-- soft law's springs launch them at metres per second), and the column's
-- collapse would start from whatever that left.
sim:fill { region = { box = { lo = { 0, 0 }, hi = { p.width, height } } }, count = p.particles,
           radius_min = p.radius_min, radius_max = p.radius_max, material = "glass", seed = p.seed,
           overlap = false }
sim:gravity { 0, -9.81 }
local file = sim:output { snapshot_every = 0.05 }

-- Calm: a kinetic energy (spins too) below that of all the spheres moving at 10 %
-- of sqrt(g d) for the mean diameter, at any size (granule.calm).
local calm = granule.calm(sim, 0.1 * math.sqrt(9.81 * (p.radius_min + p.radius_max)))
-- The fill lets the spheres go at rest: they are calm before they fall, so the
-- column is not settled before one from the top of the fill could have
-- reached the floor, sqrt(2 h / g) (0.13 s for the default 80 mm).
local fall_time = math.sqrt(2 * height / 9.81)
granule.stage(sim, { name = "fill", duration = math.max(0.5, 2 * fall_time), check_every = 500,
                     stop_when = function(s) return s:time() > fall_time and calm(s) end })
-- Pulled away faster than the column falls, to 50 column widths off (beyond
-- any run-out: 1 m at the default width).
local gate_away = 50 * p.width
sim:set_wall("gate", { velocity = { 20, 0 } })
granule.stage(sim, { name = "collapse", duration = gate_away / 20 })
sim:set_wall("gate", { velocity = { 0, 0 } })
granule.stage(sim, { name = "settle", duration = p.duration, check_every = 500, stop_when = calm })

-- The surface: the top of the highest particle in each bin.
local bin = 2 * p.radius_max
local top, reach = {}, 0
for _, id in ipairs(sim:particles()) do
  local b = sim:particle(id)
  local x, y = b.position[1], b.position[2] + b.radius
  if y > 0 and x > 0 and x < gate_away then
    local k = math.floor(x / bin)
    if not top[k] or y > top[k] then top[k] = y end
    reach = math.max(reach, x + b.radius)
  end
end
local n, sx, sy, sxx, sxy = 0, 0, 0, 0, 0
for k, y in pairs(top) do
  local x = (k + 0.5) * bin
  if x > 0.15 * reach and x < 0.85 * reach then
    n, sx, sy, sxx, sxy = n + 1, sx + x, sy + y, sxx + x * x, sxy + x * y
  end
end
-- A line needs three bins of surface at least; fewer (a handful of spheres)
-- fit no angle.
if n < 3 then
  sim:result { run_out = reach, rolling_friction = p.rolling_friction }
  print(string.format("repose_rolling: mu_r = %g (%s), seed %d: no angle (the surface spans %d bin%s between " ..
    "15 and 85 %% of the run-out, 3 needed: particles=%d too few), run-out %.4g m, t = %.3f s",
    p.rolling_friction, p.rolling_model, p.seed, n, n == 1 and "" or "s", p.particles, reach, sim:time()))
else
  local slope = (n * sxy - sx * sy) / (n * sxx - sx * sx)
  local angle = math.deg(math.atan(-slope))
  sim:result { angle = angle, run_out = reach, rolling_friction = p.rolling_friction }
  print(string.format("repose_rolling: mu_r = %g (%s), seed %d: angle %.2f deg, run-out %.4g m, t = %.3f s",
    p.rolling_friction, p.rolling_model, p.seed, angle, reach, sim:time()))
end
print("results written to " .. file)
