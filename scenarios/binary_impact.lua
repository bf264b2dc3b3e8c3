-- Binary impact of two spheres (dissertation 3.4, Fig. 3.3; Table 3.1 defaults),
-- or of one sphere on a flat wall (target = "wall").
--
-- Sphere A comes from the left, B from the right; their relative velocity has
-- magnitude `velocity` and makes `angle` degrees with the line of centres
-- (0 = head-on) when they touch (granule.impact.start starts each back along
-- its own path). Each sphere spins at `spin` rad/s about z. The run records the
-- force paths of Figs 3.4-3.8 into the /impact series and prints one summary line.
-- A run of more than 1e8 steps (a tiny restitution's tiny time step) is refused.
--
--   granule run scenarios/binary_impact.lua -D velocity=1 -D angle=30
--   /usr/bin/python3 tools/plot_binary_impact.py binary_impact.h5
local granule = require "granule"
local impact = require "granule.impact"

local p = parameters {
  velocity = { default = 1.0, above = 0, unit = "m/s", doc = "relative impact speed" },
  angle = { default = 0.0, min = 0, below = 90, unit = "deg", doc = "angle between relative velocity and line of centres" },
  spin = { default = 0.0, unit = "rad/s", doc = "initial spin of each sphere about z" },
  model = { default = "walton_braun", doc = "walton_braun | linear | hertz_mindlin | thornton_elastic | thornton_jkr" },
  target = { default = "sphere", doc = "sphere | wall" },
  dimension = { default = 2, integer = true, min = 2, max = 3, doc = "2 or 3" },
  radius = { default = 0.2e-3, above = 0, unit = "m" },
  density = { default = 1200, above = 0, unit = "kg/m^3" },
  k_load = { default = 20000, above = 0, unit = "N/m", doc = "loading stiffness (linear: k_normal)" },
  restitution = { default = 0.85, above = 0, max = 1, unit = "-" },
  friction = { default = 0.4, min = 0, unit = "-" },
  tangential_ratio = { default = 0.8, above = 0, unit = "-", doc = "initial tangential / normal stiffness (walton_braun: tau of Eq. 3.4, > 0)" },
  young = { default = 0.0, min = 0, unit = "Pa", doc = "Young's modulus (Thornton models)" },
  poisson = { default = 0.0, above = -1, max = 0.5, unit = "-", doc = "Poisson's ratio (Thornton models)" },
  surface_energy = { default = 0.0, min = 0, unit = "J/m^2", doc = "surface energy (JKR model)" },
  steps_per_contact = { default = 40, above = 0, unit = "-", doc = "n of Eq. 4.1 (linear, hertz_mindlin: 160 or more where e < 0.2 matters)" },
  allow_tension = { default = 1, integer = true, min = 0, max = 1, unit = "-", doc = "linear: 1 the dashpot may pull at the end of an impact; 0 N >= 0" },
  calibrate_restitution = { default = 1, integer = true, min = 0, max = 1, unit = "-", doc = "hertz_mindlin: 1 damping solved for e; 0 the EDEM/LIGGGHTS formula" },
  shrink_rescale = { default = 0, integer = true, min = 0, max = 1, unit = "-", doc = "Thornton models: 1 scales T, T*, T** with the contact radius while N falls" },
  start_gap = { default = 0.01, above = 0, max = 1, unit = "-", doc = "distance closed before touching, as a fraction of the radius (at most what one contact time closes): moves where within a step the contact starts" },
}

assert(p.angle >= 0 and p.angle < 90, "angle must be in [0, 90) degrees")
assert(p.velocity > 0, "velocity must be > 0")
assert(p.target == "sphere" or p.target == "wall", "target must be 'sphere' or 'wall'")

local sim = simulation { dimension = p.dimension, steps_per_contact = p.steps_per_contact,
                         record_contacts = true }
sim:material { name = "particle", density = p.density, young = p.young, poisson = p.poisson,
               surface_energy = p.surface_energy }
sim:material { name = "wall", density = 0, young = p.young, poisson = p.poisson,
               surface_energy = p.surface_energy }

local function law(model)
  if model == "walton_braun" then
    return { model = model, k_load = p.k_load, restitution = p.restitution, friction = p.friction,
             tangential_ratio = p.tangential_ratio }
  elseif model == "linear" then
    return { model = model, k_normal = p.k_load, restitution = p.restitution, friction = p.friction,
             tangential_ratio = p.tangential_ratio, allow_tension = p.allow_tension }
  elseif model == "hertz_mindlin" then   -- E*, G* from young and poisson (-D young=... -D poisson=...)
    return { model = model, restitution = p.restitution, friction = p.friction,
             calibrate_restitution = p.calibrate_restitution }
  elseif model == "thornton_elastic" then  -- Hertz + Mindlin-Deresiewicz (6.3.2), elastic: e = 1
    return { model = model, friction = p.friction, shrink_rescale = p.shrink_rescale }
  elseif model == "thornton_jkr" then      -- JKR + Savkoor-Briggs (6.3.3), Gamma = surface_energy
    return { model = model, friction = p.friction, surface_energy = p.surface_energy,
             shrink_rescale = p.shrink_rescale }
  end
  error("unknown model '" .. model .. "' (walton_braun, linear, hertz_mindlin, thornton_elastic, thornton_jkr)")
end
for _, other in ipairs { "particle", "wall" } do
  local c = law(p.model)
  c[1], c[2] = "particle", other
  sim:contact(c)
end

local r = p.radius
local m = granule.sphere_mass(r, p.density)
local m_eff = p.target == "wall" and m or m / 2
local r_eff = p.target == "wall" and r or r / 2
local normal_speed = p.velocity * math.cos(math.rad(p.angle))
-- One contact's duration: the linear spring's pi sqrt(m*/K), Hertz's
-- 2.868 (m*^2/(R* E*^2 v_n))^(1/5) for the models built on it, and for
-- Walton-Braun the loading, unloading and latched overlap of Eqs. 3.1-3.2.
local one_contact = math.pi * math.sqrt(m_eff / p.k_load)
if p.young > 0 then
  local e_star = 1 / (2 * (1 - p.poisson ^ 2) / p.young)
  one_contact = math.max(one_contact, 2.868 * (m_eff ^ 2 / (r_eff * e_star ^ 2 * normal_speed)) ^ 0.2)
end
if p.model == "walton_braun" then
  one_contact = math.max(one_contact, impact.walton_braun_duration { mass = m_eff, k_load = p.k_load,
                                                                     restitution = p.restitution })
end
-- The bodies close start_gap r (default 1 % of r) along the line of centres
-- before they touch, in at most one contact's time, and touch with the line
-- of centres along x, so the angle at contact is `angle`.
local lead_time = impact.lead_time { gap = p.start_gap * r, velocity = p.velocity, angle_deg = p.angle, cap = one_contact }
local start = impact.start { radius = r, velocity = p.velocity, angle_deg = p.angle, lead_time = lead_time,
                             target = p.target, dimension = p.dimension }
local spin = p.dimension == 3 and { 0, 0, p.spin } or p.spin
local a, b
a = sim:add_particle { position = start.a.position, velocity = start.a.velocity, spin = spin, radius = r,
                       material = "particle" }
if p.target == "sphere" then
  b = sim:add_particle { position = start.b.position, velocity = start.b.velocity, spin = spin, radius = r,
                         material = "particle" }
else
  sim:wall_plane { name = "target", point = p.dimension == 3 and { 0, 0, 0 } or { 0, 0 },
                   normal = p.dimension == 3 and { -1, 0, 0 } or { -1, 0 }, material = "wall" }
end

-- Time allowed for the contact: 20 contact times. An adhesive sphere that is
-- still in contact then has stuck (restitution 0).
local dt = sim:time_step()
local contact_time = 20 * one_contact
-- A run the contact itself makes absurdly long is refused naming what to
-- change: the impact's own steps (approach and one contact; the run stops
-- when the contact ends) at most 1e8.
local advice = {
  walton_braun = string.format("raise restitution (%g: the time step pi e sqrt(m/2K)/n of Eq. 4.1 falls with e, " ..
                 "and the latched overlap takes sqrt(m*/K) (1 - e^2)/e to clear) or lower steps_per_contact (%g)",
                 p.restitution, p.steps_per_contact),
  linear = string.format("raise restitution (%g) or lower steps_per_contact (%g)", p.restitution, p.steps_per_contact),
}
impact.check_steps("binary_impact", (lead_time + one_contact) / dt, 1e8,
  string.format("time step %.3g s, %.3g s to simulate; ", dt, lead_time + one_contact) ..
  (advice[p.model] or string.format("raise velocity (%g) or lower angle (%g) (a Hertz contact lasts as " ..
   "(velocity cos(angle))^(-1/5)) or lower steps_per_contact (%g)", p.velocity, p.angle, p.steps_per_contact)))

-- The dashpot laws' rebound carries a time-step error that grows as e falls
-- (docs/contact_models.md: hertz_mindlin at e = 0.02, 5 m/s is 13 % low at
-- n = 40, 2 % at n = 160), so a low e at a coarse step is worth a word.
if (p.model == "linear" or p.model == "hertz_mindlin") and p.restitution < 0.2 and p.steps_per_contact < 160 then
  io.stderr:write(string.format("binary_impact: warning: restitution=%g at steps_per_contact=%g rebounds " ..
    "off e by a time-step error that grows as e falls; use steps_per_contact=160 or more\n",
    p.restitution, p.steps_per_contact))
end

local out = sim:output {}
sim:series("impact", { "time", "overlap", "normal_force", "tangential_force" })

-- Relative state of B with respect to A (or of the wall with respect to A):
-- normal approach speed, tangential speed, and the unit normal from B to A.
local function relative()
  local pa = sim:particle(a)
  local xb, vb = { r + 0, 0 }, { 0, 0 }
  local normal
  if b then
    local pb = sim:particle(b)
    xb, vb = pb.position, pb.velocity
    normal = granule.vec.unit(granule.vec.sub(pa.position, xb))
  else
    normal = { -1, 0 }
  end
  local v = granule.vec.sub({ vb[1], vb[2] }, { pa.velocity[1], pa.velocity[2] })
  local n2 = { normal[1], normal[2] }
  local vn = granule.vec.dot(v, n2)
  local tangent = { -n2[2], n2[1] }
  return vn, granule.vec.dot(v, tangent), tangent
end

local vn_before = relative()
local function kinetic_energy()  -- translational and rotational
  local s = sim:stats()
  return s.kinetic_energy_translational + s.kinetic_energy_rotational
end
local energy_before = kinetic_energy()
local touching_steps, contact_steps, max_overlap, max_normal, seen, ended = 0, 0, 0, 0, false, false
sim:every { steps = 1, function(s)
  local list = s:contacts()
  if #list == 0 then
    if seen then ended = true end
    return
  end
  seen = true
  local c = list[1]
  local tangent = { -c.normal[2], c.normal[1] }
  local t_signed = c.tangential_force[1] * tangent[1] + c.tangential_force[2] * tangent[2]
  s:append("impact", { s:time(), c.overlap, c.normal_force, t_signed })
  contact_steps = contact_steps + 1
  if c.normal_force > 0 then touching_steps = touching_steps + 1 end
  if c.overlap > max_overlap then max_overlap = c.overlap end
  if c.normal_force > max_normal then max_normal = c.normal_force end
end }

sim:run { duration = lead_time + contact_time, check_every = 1, stop_when = function() return ended end }
assert(seen, "the spheres never touched")
local stuck = not ended
assert(not stuck or p.model == "thornton_jkr", "the contact did not end within the time allowed")

local vn_after, vt_after = relative()
-- A stuck pair has no rebound: its relative velocity at the end is the
-- contact's vibration, not a rebound, so it reads 0.
if stuck then vn_after, vt_after = 0, 0 end
local result = {
  model = p.model,
  target = p.target,
  velocity = p.velocity,
  angle = p.angle,
  rebound_normal_velocity = -vn_after,
  rebound_tangential_velocity = vt_after,
  spin_a = p.dimension == 2 and sim:particle(a).spin or sim:particle(a).spin[3],
  spin_b = b and (p.dimension == 2 and sim:particle(b).spin or sim:particle(b).spin[3]) or 0,
  restitution = stuck and 0 or -vn_after / vn_before,
  stuck = stuck,
  contact_duration = touching_steps * dt,
  contact_time = contact_steps * dt,
  max_overlap = max_overlap,
  max_normal_force = max_normal,
  energy_ratio = kinetic_energy() / energy_before,
  time_step = dt,
}
sim:result { restitution = result.restitution, contact_duration = result.contact_duration,
             contact_time = result.contact_time,
             max_overlap = result.max_overlap, max_normal_force = result.max_normal_force,
             rebound_normal_velocity = result.rebound_normal_velocity,
             rebound_tangential_velocity = result.rebound_tangential_velocity,
             spin_a = result.spin_a, spin_b = result.spin_b, energy_ratio = result.energy_ratio }
print(granule.summary_line(result, { "model", "target", "velocity", "angle", "rebound_normal_velocity",
  "rebound_tangential_velocity", "spin_a", "spin_b", "restitution", "stuck", "contact_duration", "contact_time", "max_overlap",
  "max_normal_force", "energy_ratio", "time_step" }))
io.stderr:write("wrote " .. out .. "\n")
