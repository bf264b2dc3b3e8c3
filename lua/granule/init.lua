-- granule: the Lua library that scenes load with `local granule = require "granule"`.
-- Small helpers that make scenes read like the experiment; the physics is in C++.
local granule = {}

granule.pi = math.pi

--- Angular velocity in rad/s from revolutions per minute.
function granule.rpm(revolutions_per_minute)
  return revolutions_per_minute * 2 * math.pi / 60
end

--- Eq. 4.2: normal stiffness K_N = 0.01 pi E r [N/m] that keeps the maximum
--- deformation below 1 % of the diameter.
function granule.stiffness_from_young(young, radius)
  return 0.01 * math.pi * young * radius
end

--- Sphere mass m = (4/3) pi r^3 rho (Eq. 4.7's pi d^3 rho / 6).
function granule.sphere_mass(radius, density)
  return 4 / 3 * math.pi * radius ^ 3 * density
end

--- Eq. 4.1: dt = pi e sqrt(m / (2 K)) / n for two equal spheres of mass m.
function granule.walton_braun_time_step(mass, k_load, restitution, steps_per_contact)
  return math.pi * restitution * math.sqrt(mass / (2 * k_load)) / (steps_per_contact or 40)
end

-- Small vector helpers (2 or 3 components).
local vec = {}
granule.vec = vec
function vec.add(a, b) local r = {} for i = 1, #a do r[i] = a[i] + b[i] end return r end
function vec.sub(a, b) local r = {} for i = 1, #a do r[i] = a[i] - b[i] end return r end
function vec.scale(a, s) local r = {} for i = 1, #a do r[i] = a[i] * s end return r end
function vec.dot(a, b) local s = 0 for i = 1, #a do s = s + a[i] * b[i] end return s end
function vec.norm(a) return math.sqrt(vec.dot(a, a)) end
function vec.unit(a) return vec.scale(a, 1 / vec.norm(a)) end
--- The 2D vector at `angle` radians from +x with length `length` (default 1).
function vec.polar(angle, length) length = length or 1 return { length * math.cos(angle), length * math.sin(angle) } end

--- Positions of `count` touching spheres of `radius` in a straight row that
--- starts (first centre) at `start` and runs along `direction`.
function granule.particle_row(start, direction, count, radius)
  local u = vec.unit(direction)
  local positions = {}
  for k = 0, count - 1 do positions[#positions + 1] = vec.add(start, vec.scale(u, 2 * radius * k)) end
  return positions
end

--- One summary line "key=value key=value ..." with keys in the given order.
function granule.summary_line(values, order)
  local parts = {}
  for _, key in ipairs(order) do
    local v = values[key]
    if type(v) == "number" then
      parts[#parts + 1] = string.format("%s=%.6g", key, v)
    else
      parts[#parts + 1] = string.format("%s=%s", key, tostring(v))
    end
  end
  return table.concat(parts, " ")
end

--- Runs one stage of a protocol and reports how it ended.
---   granule.stage(sim, { name = "settle", duration = 0.1, stop_when = function(sim) ... end,
---                        check_every = 100, quiet = false })
--- Returns the table sim:run returns (steps, time, stopped).
function granule.stage(sim, spec)
  local run = { check_every = spec.check_every, stop_when = spec.stop_when }
  if spec.steps then run.steps = spec.steps else run.duration = spec.duration end
  local result = sim:run(run)
  if not spec.quiet then
    io.stderr:write(string.format("stage %-20s t = %.6g s after %d steps (%s)\n", spec.name or "?",
      result.time, result.steps, result.stopped and "criterion met" or "time limit"))
  end
  return result
end

return granule
