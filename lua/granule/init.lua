-- granule: the Lua library that scenes load with `local granule = require "granule"`.
-- Small helpers that make scenes read like the experiment; the physics is in C++.
local granule = {}

-- Every function here is exported through `export`, which checks the number
-- and the types of its arguments against its entry in the API documentation
-- table (src/lua/api_docs.cpp, the same one help() prints), so a wrong call
-- fails at the caller's line with a message instead of deep inside.
local docs = {}
for _, d in ipairs(api_reference()) do docs[d.name] = d end

local function finite(v) return type(v) == "number" and v == v and v ~= math.huge and v ~= -math.huge end

local checks = {
  number = finite,
  integer = function(v) return finite(v) and v == math.floor(v) end,
  string = function(v) return type(v) == "string" end,
  boolean = function(v) return type(v) == "boolean" end,
  table = function(v) return type(v) == "table" end,
  list = function(v) return type(v) == "table" end,
  ["function"] = function(v) return type(v) == "function" end,
  vector = function(v)
    if type(v) ~= "table" or #v < 2 or #v > 3 then return false end
    for i = 1, #v do if not finite(v[i]) then return false end end
    return true
  end,
  any = function() return true end,
}

-- What a refused argument was, down to the bad component of a vector.
local function describe_value(v)
  if type(v) == "number" then return v ~= v and "nan" or tostring(v) end
  if type(v) ~= "table" then return type(v) end
  if #v < 2 or #v > 3 then return string.format("a table of %d component%s", #v, #v == 1 and "" or "s") end
  for i = 1, #v do
    if not finite(v[i]) then return string.format("component %d = %s", i, describe_value(v[i])) end
  end
  return "a table"
end

local function export(name, fn)
  local d = assert(docs[name], "granule library: no documentation entry for " .. name)
  local most, least = #d.args, 0
  for i, a in ipairs(d.args) do if a.required then least = i end end
  return function(...)
    local n = select("#", ...)
    if n < least or n > most then
      error(string.format("%s expects %s arguments, got %d (usage: %s)", name,
        least == most and tostring(least) or (least .. " to " .. most), n, d.signature), 2)
    end
    for i, a in ipairs(d.args) do
      local v = select(i, ...)
      if v ~= nil or a.required then
        if not checks[a.type](v) then
          error(string.format("%s: argument %d (%s) must be a %s%s, got %s", name, i, a.doc, a.type,
            a.type == "number" and " (finite)" or a.type == "vector" and " (2 or 3 finite numbers)" or "",
            describe_value(v)), 2)
        end
      end
    end
    return fn(...)
  end
end

granule.pi = math.pi

--- Angular velocity in rad/s from revolutions per minute.
granule.rpm = export("granule.rpm", function(revolutions_per_minute)
  return revolutions_per_minute * 2 * math.pi / 60
end)

--- Eq. 4.2: normal stiffness K_N = 0.01 pi E r [N/m] that keeps the maximum
--- deformation below 1 % of the diameter.
granule.stiffness_from_young = export("granule.stiffness_from_young", function(young, radius)
  return 0.01 * math.pi * young * radius
end)

--- Sphere mass m = (4/3) pi r^3 rho (Eq. 4.7's pi d^3 rho / 6).
granule.sphere_mass = export("granule.sphere_mass", function(radius, density)
  if not (radius > 0) or not (density > 0) then
    error(string.format("granule.sphere_mass: radius (%s m) and density (%s kg/m^3) must be > 0",
      tostring(radius), tostring(density)), 2)
  end
  return 4 / 3 * math.pi * radius ^ 3 * density
end)

--- Eq. 4.1: dt = pi e sqrt(m / (2 K)) / n for two equal spheres of mass m.
granule.walton_braun_time_step = export("granule.walton_braun_time_step", function(mass, k_load, restitution, steps_per_contact)
  if not (mass > 0) or not (k_load > 0) or not (restitution > 0 and restitution <= 1) or
     not ((steps_per_contact or 40) > 0) then
    error(string.format("granule.walton_braun_time_step: mass (%s kg) and k_load (%s N/m) must be > 0, " ..
      "restitution (%s) in (0, 1] and steps_per_contact (%s) > 0", tostring(mass), tostring(k_load),
      tostring(restitution), tostring(steps_per_contact or 40)), 2)
  end
  return math.pi * restitution * math.sqrt(mass / (2 * k_load)) / (steps_per_contact or 40)
end)

-- Small vector helpers (2 or 3 components).
local vec = {}
granule.vec = vec
local function same_length(name, a, b)
  if #a ~= #b then error(string.format("%s: the vectors have %d and %d components", name, #a, #b), 3) end
end
vec.add = export("granule.vec.add", function(a, b)
  same_length("granule.vec.add", a, b)
  local r = {} for i = 1, #a do r[i] = a[i] + b[i] end return r
end)
vec.sub = export("granule.vec.sub", function(a, b)
  same_length("granule.vec.sub", a, b)
  local r = {} for i = 1, #a do r[i] = a[i] - b[i] end return r
end)
vec.scale = export("granule.vec.scale", function(a, s) local r = {} for i = 1, #a do r[i] = a[i] * s end return r end)
vec.dot = export("granule.vec.dot", function(a, b)
  same_length("granule.vec.dot", a, b)
  local s = 0 for i = 1, #a do s = s + a[i] * b[i] end return s
end)
vec.norm = export("granule.vec.norm", function(a) return math.sqrt(vec.dot(a, a)) end)
vec.unit = export("granule.vec.unit", function(a)
  local n = vec.norm(a)
  if not (n > 0) or n == math.huge then error("granule.vec.unit: the vector has no direction (length " .. n .. ")", 3) end
  return vec.scale(a, 1 / n)
end)
--- The 2D vector at `angle` radians from +x with length `length` (default 1).
vec.polar = export("granule.vec.polar", function(angle, length) length = length or 1 return { length * math.cos(angle), length * math.sin(angle) } end)

--- Positions of `count` touching spheres of `radius` in a straight row that
--- starts (first centre) at `start` and runs along `direction`.
granule.particle_row = export("granule.particle_row", function(start, direction, count, radius)
  if count < 0 or count > 1e7 then error("granule.particle_row: count must be 0..1e7, got " .. count, 3) end
  if not (radius > 0) then error("granule.particle_row: radius must be > 0 [m], got " .. radius, 3) end
  local u = vec.unit(direction)
  local positions = {}
  for k = 0, count - 1 do positions[#positions + 1] = vec.add(start, vec.scale(u, 2 * radius * k)) end
  return positions
end)

--- One summary line "key=value key=value ..." with keys in the given order.
granule.summary_line = export("granule.summary_line", function(values, order)
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
end)

--- A stop_when criterion for a settling stage that holds at any particle size:
--- calm when the kinetic energy (translational and rotational) is below that
--- of the free particles' whole mass moving at rest_speed, E < M v^2 / 2
--- (or when no particle is free), at `checks` calls in a row (default 1).
--- Scenes give rest_speed as a fraction of their own speed scale (sqrt(g d)
--- under gravity), not an energy in joules, which would be met at once by
--- micron beads and never by centimetre ones. A bed that rings as a whole (a
--- tall column on a soft floor) passes near zero kinetic energy twice a period;
--- checks = 3 asks for calm at three checks in a row, which such a ringing
--- meets only once it has died down. The count is of its own calls: call it
--- at every check (first in an `and`), and make one per stage.
granule.calm = export("granule.calm", function(sim, rest_speed, checks)
  if type(sim) ~= "userdata" then
    error("granule.calm: the first argument must be the simulation, got " .. type(sim), 2)
  end
  if not (rest_speed > 0) then
    error(string.format("granule.calm: rest_speed must be > 0 m/s, got %s", tostring(rest_speed)), 2)
  end
  checks = checks == nil and 1 or (math.tointeger(checks) or checks)  -- 3.0 is 3
  if math.type(checks) ~= "integer" or checks < 1 then
    error(string.format("granule.calm: checks must be a whole number >= 1, got %s", tostring(checks)), 2)
  end
  -- The free mass from sim:stats() (one reduction under mpirun, no whole-scene
  -- call): it follows particles added, removed, fixed and freed. With none
  -- free, nothing moves: calm.
  local in_a_row = 0
  return function(s)
    local stats = s:stats()
    local mass = stats.free_mass
    local now = mass == 0 or stats.kinetic_energy < 0.5 * mass * rest_speed * rest_speed
    in_a_row = now and in_a_row + 1 or 0
    return in_a_row >= checks
  end
end)

--- Runs one stage of a protocol and reports how it ended.
---   granule.stage(sim, { name = "settle", duration = 0.1, stop_when = function(sim) ... end,
---                        check_every = 100, quiet = false })
--- Returns the table sim:run returns (steps, time, stopped).
local stage_keys = { name = true, duration = true, steps = true, stop_when = true, check_every = true, quiet = true }
granule.stage = export("granule.stage", function(sim, spec)
  if type(sim) ~= "userdata" then
    error("granule.stage: the first argument must be the simulation, got " .. type(sim), 2)
  end
  for key in pairs(spec) do
    if not stage_keys[key] then error("granule.stage: unknown key '" .. tostring(key) .. "'", 2) end
  end
  if (spec.steps == nil) == (spec.duration == nil) then
    error("granule.stage: give exactly one of steps = N or duration = T [s]", 2)
  end
  local run = { check_every = spec.check_every, stop_when = spec.stop_when }
  if spec.steps then run.steps = spec.steps else run.duration = spec.duration end
  local result = sim:run(run)
  if not spec.quiet then
    io.stderr:write(string.format("stage %-20s t = %.6g s after %d steps (%s)\n", spec.name or "?",
      result.time, result.steps,
      result.interrupted and "interrupted" or result.stopped and "criterion met" or "time limit"))
  end
  return result
end)

return granule
