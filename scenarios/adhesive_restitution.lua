-- Restitution of an adhesive elastic sphere against a wall as a function of
-- impact velocity (Thornton's JKR model, dissertation 6.3.3): below a critical
-- velocity the sphere sticks (restitution 0), above it the restitution rises
-- towards 1. Each velocity is a fresh sphere in the same simulation; the sweep
-- goes to the series /sweep and to a table on stdout.
--
--   granule run scenarios/adhesive_restitution.lua -D surface_energy=0.2
--   /usr/bin/python3 tools/plot_series.py adhesive_restitution.h5 --group /sweep --x velocity
local p = parameters {
  radius = { default = 5e-6, above = 0, unit = "m" },
  density = { default = 3970, above = 0, unit = "kg/m^3", doc = "Al2O3 (dissertation 7.3)" },
  young = { default = 345e9, above = 0, unit = "Pa" },
  poisson = { default = 0.26 , above = -1, max = 0.5},
  wall_young = { default = 1000e9, above = 0, unit = "Pa" },
  wall_poisson = { default = 0.45 , above = -1, max = 0.5},
  surface_energy = { default = 1.0, min = 0, unit = "J/m^2" },
  friction = { default = 0.25 , min = 0},
  v_min = { default = 0.01, above = 0, unit = "m/s" },
  v_max = { default = 3.0, above = 0, max = 1e4, unit = "m/s" },
  count = { default = 12, integer = true, min = 2, max = 10000, doc = "number of velocities, log-spaced" },
  dimension = { default = 3 , integer = true, min = 2, max = 3},
  steps_per_contact = { default = 40, above = 0, doc = "n of Eq. 4.1 (the step is 8 T_R / n, T_R the sphere's Rayleigh time); above ~3 m/s the Hertz contact is shorter than 8 T_R, so raise n with v_max" },
}
assert(p.v_min < p.v_max, string.format("v_min (%g m/s) must be below v_max (%g m/s)", p.v_min, p.v_max))
-- The -D values, checked before anything runs.
local checks = require "granule.checks"
for name, unit in pairs { radius = "m", v_min = "m/s", v_max = "m/s" } do
  checks.positive("adhesive_restitution", name, p[name], unit)
end
checks.non_negative("adhesive_restitution", "surface_energy", p.surface_energy, "J/m^2")
checks.positive("adhesive_restitution", "steps_per_contact", p.steps_per_contact)
if not (p.count >= 1 and p.count == math.floor(p.count)) then
  checks.fail("adhesive_restitution", "count", "a whole number >= 1", p.count)
end
local sim = simulation { dimension = p.dimension, record_contacts = true,
                         steps_per_contact = p.steps_per_contact }
sim:material { name = "alumina", density = p.density, young = p.young, poisson = p.poisson }
sim:material { name = "wall", young = p.wall_young, poisson = p.wall_poisson }
sim:contact { "alumina", "wall", model = "thornton_jkr", friction = p.friction, surface_energy = p.surface_energy }
sim:contact { "alumina", "alumina", model = "thornton_jkr", friction = p.friction, surface_energy = p.surface_energy }
local function v(x) if p.dimension == 3 then return { x, 0, 0 } end return { x, 0 } end
sim:wall_plane { name = "target", point = v(0), normal = v(-1), material = "wall" }
local out = sim:output {}
sim:series("sweep", { "velocity", "restitution", "contact_time" })
print("velocity_m_s restitution contact_time_s")
local r = p.radius
for k = 0, p.count - 1 do
  local speed = p.v_min * (p.v_max / p.v_min) ^ (k / math.max(1, p.count - 1))
  for _, id in ipairs(sim:particles()) do sim:remove_particle(id) end
  local a = sim:add_particle { position = v(-r - 1e-3 * r), velocity = v(speed), radius = r, material = "alumina" }
  local seen, ended, t_contact = false, false, 0
  local hook = sim:every { steps = 1, function(s)
    if #s:contacts() > 0 then
      seen = true
      t_contact = t_contact + s:time_step()
    elseif seen then
      ended = true
    end
  end }
  -- A stuck sphere never leaves: cap the run at 100 Hertz contact times
  -- (2.868 (m*^2/(R* E*^2 v))^(1/5), Johnson 1985) after the approach.
  local mass = 4 / 3 * math.pi * r ^ 3 * p.density
  local e_star = 1 / ((1 - p.poisson ^ 2) / p.young + (1 - p.wall_poisson ^ 2) / p.wall_young)
  local hertz_time = 2.868 * (mass ^ 2 / (r * e_star ^ 2 * speed)) ^ 0.2
  sim:run { duration = 1e-3 * r / speed + 100 * hertz_time, check_every = 20,
            stop_when = function() return ended end }
  sim:remove_hook(hook)
  local e = ended and -sim:particle(a).velocity[1] / speed or 0
  sim:append("sweep", { speed, e, t_contact })
  print(string.format("%.5g %.5g %.4g", speed, e, t_contact))
end
io.stderr:write("wrote " .. out .. "\n")
