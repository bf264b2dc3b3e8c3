-- granule.impact: the starting states and time limits of a single impact, two
-- equal spheres or a sphere on a flat wall (scenarios/binary_impact.lua,
-- scenarios/binary_impact_map.lua).
--
--   local impact = require "granule.impact"
--   local lead = impact.lead_time { gap = 0.01 * r, velocity = 1, angle_deg = 30, cap = t_contact }
--   local s = impact.start { radius = r, velocity = 1, angle_deg = 30, lead_time = lead, dimension = 2 }
--   sim:add_particle { position = s.a.position, velocity = s.a.velocity, radius = r, material = "particle" }
--
-- The bodies touch at t = lead_time with the line of centres along x: each
-- sphere starts lead_time back along its own straight path from the touching
-- position (A at (-r, 0), B at (r, 0); on a wall A alone, the wall the plane
-- x = 0). Started side by side instead, the spheres drift sideways while they
-- close and the line of centres at contact turns away from the stated angle,
-- more the larger the angle: above 84.3 deg at a gap of 1 % of r they miss.
local checks = require "granule.checks"

local M = {}

local function angle_arg(where, value)
  checks.number(where, "angle_deg", value, "deg")
  if not (value >= 0 and value < 90) then checks.fail(where, "angle_deg", "in [0, 90) deg", value) end
  return value
end

--- impact.lead_time { gap = g, velocity = v, angle_deg = theta, cap = t } -> seconds:
--- the time the bodies take to close a gap g along the line of centres,
--- g / (v cos theta), but at most cap (> 0). That time grows without bound as
--- v cos theta falls; the cap (a contact time, say) keeps a grazing or slow
--- impact from spending its steps on the approach, the bodies then start
--- closer than g.
function M.lead_time(spec)
  local where = "impact.lead_time"
  checks.table_arg(where, spec, "gap, velocity, angle_deg, cap")
  checks.known_keys(where, spec, { "gap", "velocity", "angle_deg", "cap" })
  local gap = checks.positive(where, "gap", spec.gap, "m")
  local velocity = checks.positive(where, "velocity", spec.velocity, "m/s")
  local angle = angle_arg(where, spec.angle_deg)
  local cap = checks.positive(where, "cap", spec.cap, "s")
  return math.min(gap / (velocity * math.cos(math.rad(angle))), cap)
end

--- impact.start { radius = r, velocity = v, angle_deg = theta, lead_time = t,
---   target = "sphere" | "wall", dimension = 2 | 3 } -> { a = { position, velocity },
---   b = { position, velocity } (nil on a wall) }: the states that bring the
--- bodies into touch at time t, the relative velocity (of A towards B, or of A
--- towards the wall) of magnitude v at theta to the line of centres x. Two
--- spheres move at -+v/2 each, so the pair's momentum is zero.
function M.start(spec)
  local where = "impact.start"
  checks.table_arg(where, spec, "radius, velocity, angle_deg, lead_time, target, dimension")
  checks.known_keys(where, spec, { "radius", "velocity", "angle_deg", "lead_time", "target", "dimension" })
  local r = checks.positive(where, "radius", spec.radius, "m")
  local velocity = checks.positive(where, "velocity", spec.velocity, "m/s")
  local angle = math.rad(angle_arg(where, spec.angle_deg))
  local lead = checks.positive(where, "lead_time", spec.lead_time, "s")
  local target = spec.target or "sphere"
  if target ~= "sphere" and target ~= "wall" then checks.fail(where, "target", "'sphere' or 'wall'", target) end
  local dimension = spec.dimension or 2
  if dimension ~= 2 and dimension ~= 3 then checks.fail(where, "dimension", "2 or 3", dimension) end
  local function vec(x, y) if dimension == 3 then return { x, y, 0 } end return { x, y } end
  local ux, uy = math.cos(angle), math.sin(angle)
  -- Each body's own speed: the whole relative velocity on a wall, half of it each for a pair.
  local speed = target == "wall" and velocity or velocity / 2
  local back = speed * lead
  local a = { position = vec(-r - ux * back, -uy * back), velocity = vec(ux * speed, uy * speed) }
  if target == "wall" then return { a = a } end
  local b = { position = vec(r + ux * back, uy * back), velocity = vec(-ux * speed, -uy * speed) }
  return { a = a, b = b }
end

--- impact.walton_braun_duration { mass = m*, k_load = K1, restitution = e } -> seconds:
--- how long a Walton-Braun contact (Eqs. 3.1-3.2) lasts from first touch until
--- the overlap is gone. The spring loads for (pi/2) sqrt(m*/K1) and unloads
--- with K2 = K1/e^2 for (pi/2) sqrt(m*/K2) down to the latched overlap
--- a0 = a_max (1 - e^2), a_max = v sqrt(m*/K1); the bodies then leave it at
--- the rebound speed e v with no force, in a0 / (e v) = sqrt(m*/K1) (1 - e^2) / e,
--- independent of v. That last part dominates at small e (1e-4 s for the
--- spheres of Table 3.1 at e = 0.01, 30 times the loading).
function M.walton_braun_duration(spec)
  local where = "impact.walton_braun_duration"
  checks.table_arg(where, spec, "mass, k_load, restitution")
  checks.known_keys(where, spec, { "mass", "k_load", "restitution" })
  local m = checks.positive(where, "mass", spec.mass, "kg")
  local k1 = checks.positive(where, "k_load", spec.k_load, "N/m")
  local e = checks.half_open(where, "restitution", spec.restitution, 0, 1)
  local root = math.sqrt(m / k1)
  return math.pi / 2 * root * (1 + e) + root * (1 - e * e) / e
end

--- impact.check_steps(where, steps, limit, advice): refuses a run of more
--- than `limit` steps with "where: the run needs N steps (more than limit);
--- advice", so a parameter that makes the time step tiny or the run long is
--- named before hours go by.
function M.check_steps(where, steps, limit, advice)
  if not (steps <= limit) then
    checks.raise(string.format("%s: the run needs %.3g steps (more than %.3g); %s", where, steps, limit, advice))
  end
  return steps
end

return M
