-- Maximum contact force of binary impacts against relative impact velocity
-- and angle (dissertation Fig. 4.26), with the slope c of F_max = c dv fitted
-- per angle (section 7.2 uses c = 0.02 N s/m to turn the Mechanofusion runs'
-- maximum forces into impact velocities).
--
-- Runs one two-sphere impact per (angle, velocity) pair with the particle of
-- Table 3.1 and the chosen contact law, as scenarios/binary_impact.lua does,
-- and writes to HDF5:
--   /impacts  angle, velocity, max_normal_force, max_overlap, restitution, contact_duration
--   /slopes   angle, slope (least squares through the origin), predicted_slope
--             ((K m / 2)^(1/2) cos(angle), granule.coating.max_force_slope: the undamped
--             loading spring of Walton-Braun; the dashpot of model=linear lowers the peak), intercept
--             and slope of a free straight-line fit, worst relative residual
-- and prints one line per angle.
--
--   granule run scenarios/binary_impact_map.lua -o binary_impact_map.h5
--   /usr/bin/python3 tools/plot_impact_map.py binary_impact_map.h5 -o impact_map.png
local granule = require "granule"
local coating = require "granule.coating"
local impact = require "granule.impact"

local p = parameters {
  angles = { default = "0,15,30,45,60,75", unit = "deg", doc = "impact angles, comma-separated" },
  velocities = { default = "0.1,0.25,0.5,0.75,1,1.5,2", unit = "m/s", doc = "relative impact speeds" },
  model = { default = "walton_braun", doc = "walton_braun | linear" },
  dimension = { default = 2, integer = true, min = 2, max = 3, doc = "2 or 3" },
  radius = { default = 0.2e-3, above = 0, unit = "m", doc = "Table 3.1" },
  density = { default = 1200, above = 0, unit = "kg/m^3", doc = "Table 3.1" },
  k_load = { default = 20000, above = 0, unit = "N/m", doc = "Table 3.1 loading stiffness" },
  restitution = { default = 0.85, above = 0, max = 1, unit = "-", doc = "Table 3.1" },
  friction = { default = 0.4, min = 0, unit = "-", doc = "Table 3.1" },
  tangential_ratio = { default = 0.8, above = 0, unit = "-", doc = "initial tangential / normal stiffness (walton_braun: tau of Eq. 3.4, > 0)" },
  spin = { default = 0.0, unit = "rad/s", doc = "initial spin of each sphere" },
  steps_per_contact = { default = 40, above = 0, unit = "-", doc = "n of Eq. 4.1" },
}

local function numbers(text, name)
  local list = {}
  for item in text:gmatch("[^,%s]+") do
    local value = tonumber(item)
    if not value then error(string.format("%s: '%s' is not a number", name, item)) end
    list[#list + 1] = value
  end
  if #list == 0 then error(name .. ": give at least one value") end
  return list
end
local angles, velocities = numbers(p.angles, "angles"), numbers(p.velocities, "velocities")
for _, a in ipairs(angles) do assert(a >= 0 and a < 90, "angles must be in [0, 90) degrees, got " .. a) end
-- The free line F = c v + b needs two distinct velocities; a repeated one
-- would make its normal equations singular (0/0) once it is the only one.
local seen_velocity = {}
for _, v in ipairs(velocities) do
  assert(v > 0, "velocities must be > 0, got " .. v)
  if seen_velocity[v] then error(string.format("velocities: %g is given twice; give distinct values", v)) end
  seen_velocity[v] = true
end
assert(p.model == "walton_braun" or p.model == "linear", "model must be walton_braun or linear")

local r = p.radius
local mass = granule.sphere_mass(r, p.density)

-- One impact: A from the left, B from the right, relative velocity `velocity`
-- at `angle` to the line of centres. Each sphere starts back along its path
-- from the touching position (+-r, 0) (granule.impact.start), so at first
-- contact the line of centres is x and the angle is the nominal one; the pair
-- closes 2 % of r along x first, in at most the time allowed for the contact.
local one_contact = math.pi * math.sqrt(mass / 2 / p.k_load)
if p.model == "walton_braun" then   -- loading, unloading and the latched overlap (Eqs. 3.1-3.2)
  one_contact = math.max(one_contact, impact.walton_braun_duration { mass = mass / 2, k_load = p.k_load,
                                                                     restitution = p.restitution })
end
local contact_time = math.max(20 * math.pi * math.sqrt(mass / p.k_load), 20 * one_contact)
local function impact_run(angle, velocity)
  local sim = simulation { dimension = p.dimension, steps_per_contact = p.steps_per_contact,
                           record_contacts = true }
  sim:material { name = "particle", density = p.density }
  local law = { "particle", "particle", model = p.model, restitution = p.restitution, friction = p.friction,
                tangential_ratio = p.tangential_ratio }
  if p.model == "walton_braun" then law.k_load = p.k_load else law.k_normal = p.k_load end
  sim:contact(law)
  local u = { math.cos(math.rad(angle)), math.sin(math.rad(angle)) }
  local lead_time = impact.lead_time { gap = 0.02 * r, velocity = velocity, angle_deg = angle, cap = contact_time }
  local start = impact.start { radius = r, velocity = velocity, angle_deg = angle, lead_time = lead_time,
                               dimension = p.dimension }
  local spin = p.dimension == 3 and { 0, 0, p.spin } or p.spin
  local a = sim:add_particle { position = start.a.position, radius = r, material = "particle",
                               velocity = start.a.velocity, spin = spin }
  local b = sim:add_particle { position = start.b.position, radius = r, material = "particle",
                               velocity = start.b.velocity, spin = spin }
  impact.check_steps("binary_impact_map", (lead_time + one_contact) / sim:time_step(), 1e8,
    string.format("raise restitution (%g; the time step of Eq. 4.1 falls with e) or lower steps_per_contact (%g)",
                  p.restitution, p.steps_per_contact))
  local f_max, overlap_max, touching_steps, seen, ended = 0, 0, 0, false, false
  sim:every { steps = 1, function(s)
    local list = s:contacts()
    if #list == 0 then
      if seen then ended = true end
      return
    end
    seen = true
    local c = list[1]
    if c.normal_force > 0 then touching_steps = touching_steps + 1 end
    f_max = math.max(f_max, c.normal_force)
    overlap_max = math.max(overlap_max, c.overlap)
  end }
  sim:run { duration = lead_time * 1.5 + contact_time, check_every = 1, stop_when = function() return ended end }
  assert(seen and ended, string.format("impact at %g deg, %g m/s did not complete", angle, velocity))
  -- Normal rebound speed along the final line of centres, for the restitution.
  local pa, pb = sim:particle(a), sim:particle(b)
  local n = granule.vec.unit { pb.position[1] - pa.position[1], pb.position[2] - pa.position[2] }
  local rebound = (pb.velocity[1] - pa.velocity[1]) * n[1] + (pb.velocity[2] - pa.velocity[2]) * n[2]
  return { max_normal_force = f_max, max_overlap = overlap_max,
           restitution = rebound / (velocity * u[1]), contact_duration = touching_steps * sim:time_step() }
end

local record = simulation { dimension = 2 }
local out = record:output {}
record:series("impacts", { "angle", "velocity", "max_normal_force", "max_overlap", "restitution", "contact_duration" })
record:series("slopes", { "angle", "slope", "predicted_slope", "line_slope", "line_intercept", "worst_residual" })

local head_on_slope
for _, angle in ipairs(angles) do
  local sum_vf, sum_vv, sum_v, sum_f, rows = 0, 0, 0, 0, {}
  for _, v in ipairs(velocities) do
    local result = impact_run(angle, v)
    record:append("impacts", { angle, v, result.max_normal_force, result.max_overlap, result.restitution,
                               result.contact_duration })
    rows[#rows + 1] = { v, result.max_normal_force }
    sum_vf, sum_vv = sum_vf + v * result.max_normal_force, sum_vv + v * v
    sum_v, sum_f = sum_v + v, sum_f + result.max_normal_force
  end
  local count = #velocities
  local slope = sum_vf / sum_vv                          -- F = c v, least squares through the origin
  local line_slope, intercept = slope, 0                 -- F = c v + b (a check of linearity)
  if count >= 2 then
    line_slope = (count * sum_vf - sum_v * sum_f) / (count * sum_vv - sum_v ^ 2)
    intercept = (sum_f - line_slope * sum_v) / count
  end
  local worst = 0
  for _, row in ipairs(rows) do worst = math.max(worst, math.abs(row[2] - slope * row[1]) / (slope * row[1])) end
  local predicted = coating.max_force_slope { particle_mass_kg = mass, stiffness_n_m = p.k_load,
                                              impact_angle_deg = angle }
  record:append("slopes", { angle, slope, predicted, line_slope, intercept, worst })
  if angle == 0 then head_on_slope = slope end
  print(string.format("angle=%g slope=%.5g predicted=%.5g line_intercept=%.3g worst_residual=%.3g",
    angle, slope, predicted, intercept, worst))
end
if head_on_slope then
  record:result { head_on_slope = head_on_slope }
  print(string.format("head_on_slope=%.5g N s/m (section 7.2 uses 0.02)", head_on_slope))
end
record:close()
io.stderr:write("wrote " .. out .. "\n")
