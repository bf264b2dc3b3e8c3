-- Oblique impacts of two identical elastic spheres with and without adhesion
-- (dissertation 6.4, Figs 6.2-6.10; Thornton's models of 6.3.2-6.3.3).
-- R = 100 um, rho = 2650, E = 70 GPa, nu = 0.3, mu = 0.35; each sphere moves at
-- 0.05 m/s, their relative velocity making `angle` with the line of centres.
-- One simulation runs every case in turn (the pair is replaced between
-- cases) and writes, per case, the loading path (T vs N) and the tangential
-- force-displacement curve into the series /angle_<deg>_gamma_<J/m^2>.
--
--   granule run scenarios/oblique_impact.lua
--   /usr/bin/python3 tools/plot_oblique_impact.py oblique_impact.h5
local granule = require "granule"

local p = parameters {
  radius = { default = 100e-6, above = 0, unit = "m" },
  density = { default = 2650, above = 0, unit = "kg/m^3" },
  young = { default = 70e9, above = 0, unit = "Pa" },
  poisson = { default = 0.3 , above = -1, max = 0.5},
  friction = { default = 0.35 , min = 0},
  speed = { default = 0.05, above = 0, unit = "m/s", doc = "speed of each sphere" },
  angles = { default = "15,30,45,60,75", unit = "deg", doc = "comma-separated impact angles" },
  surface_energies = { default = "0,0.2", unit = "J/m^2", doc = "comma-separated Gamma values" },
  dimension = { default = 2 , integer = true, min = 2, max = 3},
  steps_per_contact = { default = 40, above = 0, unit = "-", doc = "n of the time-step rule (8 T_R / n for Hertz's laws)" },
  shrink_rescale = { default = 0, integer = true, min = 0, max = 1, unit = "-", doc = "1: T, T*, T** scale with the contact radius while N falls (docs/contact_models.md)" },
}

local function list(text)
  local out = {}
  for item in string.gmatch(text, "[^,]+") do out[#out + 1] = assert(tonumber(item), "not a number: " .. item) end
  return out
end

local sim = simulation { dimension = p.dimension, record_contacts = true, steps_per_contact = p.steps_per_contact }
local out = sim:output {}
local r = p.radius
local function v(x, y) if p.dimension == 3 then return { x, y, 0 } end return { x, y } end

print("gamma_J_m2 angle_deg rebound_tangential_m_s spin_a_rad_s restitution contact_time_s max_normal_N")
for _, gamma in ipairs(list(p.surface_energies)) do
  -- A material per Gamma, as a pair of materials has one law.
  local quartz = string.format("quartz_%g", gamma)
  sim:material { name = quartz, density = p.density, young = p.young, poisson = p.poisson }
  local model = gamma > 0 and "thornton_jkr" or "thornton_elastic"
  local law = { quartz, quartz, model = model, friction = p.friction, shrink_rescale = p.shrink_rescale }
  if gamma > 0 then law.surface_energy = gamma end
  sim:contact(law)
  for _, angle in ipairs(list(p.angles)) do
    for _, id in ipairs(sim:particles()) do sim:remove_particle(id) end
    local dir = { math.cos(math.rad(angle)), math.sin(math.rad(angle)) }
    -- A gap of 1e-6 R: while a wider one closes, the spheres slide past each
    -- other and the line of centres turns (by 5.7e-3 rad over 1e-3 R at 85
    -- degrees, which cuts the normal speed at contact by 7 %).
    local gap = 1e-6 * r
    local a = sim:add_particle { position = v(-r - gap / 2, 0), velocity = v(dir[1] * p.speed, dir[2] * p.speed),
                                 radius = r, material = quartz }
    local b = sim:add_particle { position = v(r + gap / 2, 0), velocity = v(-dir[1] * p.speed, -dir[2] * p.speed),
                                 radius = r, material = quartz }
    local name = string.format("angle_%g_gamma_%g", angle, gamma)
    sim:series(name, { "time", "overlap", "normal_force", "tangential_force", "tangential_displacement" })
    local displacement, seen, ended, t_contact, n_max = 0, false, false, 0, 0
    local hook = sim:every { steps = 1, function(s)
      local c = s:contacts()[1]
      if not c then
        if seen then ended = true end
        return
      end
      seen = true
      local pa, pb = s:particle(a), s:particle(b)
      local t = { -c.normal[2], c.normal[1] }
      local spin_a = p.dimension == 2 and pa.spin or pa.spin[3]
      local spin_b = p.dimension == 2 and pb.spin or pb.spin[3]
      local slip = (pb.velocity[1] - pa.velocity[1]) * t[1] + (pb.velocity[2] - pa.velocity[2]) * t[2]
                   + r * (spin_a + spin_b)
      local dt = s:time_step()
      displacement = displacement + slip * dt
      t_contact = t_contact + dt
      if c.normal_force > n_max then n_max = c.normal_force end
      s:append(name, { s:time(), c.overlap, c.normal_force,
                       c.tangential_force[1] * t[1] + c.tangential_force[2] * t[2], displacement })
    end }
    local n0 = granule.vec.unit(granule.vec.sub(sim:particle(a).position, sim:particle(b).position))
    local vn0 = granule.vec.dot(granule.vec.sub(sim:particle(b).velocity, sim:particle(a).velocity), n0)
    -- Long enough for a thousand of Hertz's contact times at the normal speed of
    -- approach (t_c = 2.87 (m*^2 / (R* E*^2 v_n))^(1/5)), whatever the scale.
    local mass = sim:particle(a).mass
    local e_star = p.young / (2 * (1 - p.poisson ^ 2))
    local v_n = math.max(vn0, 1e-3 * 2 * p.speed)
    local limit = 1000 * 2.868 * ((mass / 2) ^ 2 / (r / 2 * e_star ^ 2 * v_n)) ^ 0.2
    sim:run { duration = limit, check_every = 10, stop_when = function() return ended end }
    sim:remove_hook(hook)
    -- A restitution from an impact that never began would be a number of
    -- nothing. An adhesive pair still in contact after a thousand contact
    -- times has stuck: no rebound, restitution 0, as binary_impact reports
    -- it; its relative velocity then is the contact's vibration.
    assert(seen, string.format("angle %g, gamma %g: the spheres did not meet within %.3g s " ..
      "(speed, radius, density and young decide when they meet)", angle, gamma, limit))
    local stuck = not ended
    assert(not stuck or gamma > 0, string.format("angle %g, gamma %g: the contact did not end within %.3g s " ..
      "(1000 contact times)", angle, gamma, limit))
    local pa, pb = sim:particle(a), sim:particle(b)
    local n = granule.vec.unit(granule.vec.sub(pa.position, pb.position))
    local rel = granule.vec.sub(pb.velocity, pa.velocity)
    local t = p.dimension == 2 and { -n[2], n[1] } or { -n[2], n[1], 0 }
    local spin_a = p.dimension == 2 and pa.spin or pa.spin[3]
    local rebound_t, restitution = granule.vec.dot(rel, t), -granule.vec.dot(rel, n) / vn0
    if stuck then
      rebound_t, restitution = 0, 0
      io.stderr:write(string.format("oblique_impact: angle %g, gamma %g: the spheres stuck (in contact after 1 ms)\n",
        angle, gamma))
    end
    print(string.format("%g %g %.6g %.6g %.6g %.4g %.4g", gamma, angle, rebound_t, spin_a, restitution,
      t_contact, n_max))
  end
end
io.stderr:write("wrote " .. out .. "\n")
