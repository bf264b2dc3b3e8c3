-- What accuracy costs in time. For a chosen case, varies each knob that
-- trades accuracy for speed, one at a time from the default setting, and reports
-- per setting the error of the quantities a user cares about against a fine
-- reference run, and the wall time.
--
--   build/granule run tools/accuracy.lua -D case=impact [-D knob=steps_per_contact] [-D values=10,20,40]
--   build/granule run tools/accuracy.lua -D case=mechanofusion -D knob=stiffness
--   build/granule run tools/accuracy.lua -D case=agglomerate -D file=agglomerate_test.h5
--   build/granule run tools/accuracy.lua -D case=rolling
--   build/granule run tools/accuracy.lua -D case=bond
--   /usr/bin/python3 tools/plot_accuracy.py accuracy_impact.csv     # error vs wall time, one curve per knob
--
-- Cases and what they measure:
--   impact         binary impacts of dissertation 3.4 (Walton-Braun, 0.4 mm spheres, 1 m/s):
--                  head-on restitution, contact duration, largest overlap and force;
--                  oblique (30 deg, mu = 0.4) tangential rebound and spin; elastic
--                  (linear, e = 1) energy drift |KE_after / KE_before - 1|
--   mechanofusion  the 2D base case (Table 4.1: 1500 particles, 2000 rpm, scraper):
--                  mean normal and tangential force on the inner piece (4.4.1, the
--                  wall_force diagnostic), mean kinetic energy, largest overlap; the
--                  noise of the mean force (standard error over `blocks` blocks,
--                  relative): differences below about twice it are not significant;
--                  the mean normal force per particle in each area of 4.4.2 (areas)
--   agglomerate    wall impact of a prepared agglomerate (7.6; file from
--                  scenarios/agglomerate_prepare.lua or the ctest fixture): damage
--                  and debris ratios (7.4), largest fragment, peak wall force, impact duration
--   rolling        a sphere rolling to rest against rolling friction (mu_r = 0.1, v0 = 0.1 m/s),
--                  constant-torque and EPSD models: stopping distance, and its error
--                  against the closed form 0.7 v0^2 / (mu_r g) (EPSD: with its wind-up)
--   bond           a parallel-bonded pair's stretching and twisting periods against their
--                  closed forms (steps_per_contact: steps per axial period)
-- Knobs (each case lists those that apply):
--   steps_per_contact  n of Eq. 4.1 (dt = t_c / n)
--   stiffness          K scaled down as section 5.4 allows; forces are compared after
--                      rescaling by the K^1/2 law of Eq. 5.10 (F ~ (m K)^1/2), times
--                      and overlaps by K^-1/2; the margins K / bound of Eqs. 5.12 and
--                      5.15 are reported and a setting below either bound is marked
--   skin               neighbour-list skin in median radii (exact lists: only the
--                      cost changes, and round-off order, which a chaotic flow amplifies)
--   dimension          2D vs 3D (impacts)
--   perturbation       (agglomerate) not a knob: the impact velocity x 1.001, whose
--                      row is the noise floor of a chaotic breakage
-- Not knobs here: threads (results bit-identical for any count) and float vs
-- double (the engine computes in double only).
--
-- Output: <out>_<case>.csv (one row per setting and quantity: value, reference value,
-- relative error, wall time, steps) and <out>_<case>.md (one row per setting).
local granule = require "granule"
local kinetic = require "granule.kinetic"

local p = parameters {
  case = { default = "impact", doc = "impact | mechanofusion | agglomerate | rolling | bond" },
  knob = { default = "all", doc = "steps_per_contact | stiffness | skin | dimension | all" },
  values = { default = "", doc = "comma-separated settings of the knob (default: the case's list)" },
  reference = { default = 0, doc = "the knob's reference setting (0: the case's finest)" },
  out = { default = "accuracy", doc = "output prefix: <out>_<case>.csv and .md" },
  -- mechanofusion
  settle = { default = 0.03, unit = "s", doc = "mechanofusion: time before averaging" },
  average = { default = 0.06, unit = "s", doc = "mechanofusion: averaging time" },
  blocks = { default = 20, integer = true, min = 2, doc = "mechanofusion: blocks of the averaging time, for the noise estimate (>= 2: the scatter of one block is unknown)" },
  particles = { default = 1500, doc = "mechanofusion: particle count" },
  rpm = { default = 2000, unit = "1/min", doc = "mechanofusion: chamber speed" },
  scraper_tilt = { default = 70, unit = "deg", doc = "mechanofusion: the scraper's angle to the wall's "
    .. "tangent, as scenarios/mechanofusion_demo.lua's (40, SPEC 4.1, jams a particle against the wall)" },
  -- agglomerate
  file = { default = "agglomerate_test.h5", doc = "agglomerate: output of an agglomerate preparation" },
  velocity = { default = 1.0, unit = "m/s", doc = "agglomerate: impact velocity" },
  quiet = { default = false, doc = "print only the tables" },
  check = { default = false, doc = "impact: fail unless the error of the elastic energy falls as "
    .. "steps_per_contact grows and that of the largest force stays within (pi/n)^2/4 at n steps a "
    .. "contact (the smoke test; the peak is sampled at whole steps, within half a step of the "
    .. "force's maximum, so its error is bounded by (omega dt)^2/8 but does not fall steadily); "
    .. "rolling: fail unless the constant torque and EPSD stop within 2 % of their "
    .. "closed forms" },
}

local function list(text)
  local out = {}
  for item in tostring(text):gmatch("[^,]+") do out[#out + 1] = tonumber(item) or item end
  return out
end

-- ---------------------------------------------------------------------------
-- Cases. Each: knobs (name -> { values, reference, default }), quantities (in print
-- order, each with its kind for the stiffness rescaling: force, time, length or
-- none) and run(setting) -> { quantity = value }, steps.

local cases = {}

-- Binary impacts (dissertation 3.4).
cases.impact = {
  doc = "binary impacts, Walton-Braun (3.4)",
  knobs = {
    -- The reference far finer than the finest setting: the oblique impact's
    -- quantities converge as 1/n, so a reference at 2 n_max would halve the error
    -- reported at n_max.
    steps_per_contact = { values = { 10, 20, 40, 80, 200 }, reference = 2000, default = 40 },
    stiffness = { values = { 1, 1 / 4, 1 / 16, 1 / 64, 1 / 256 }, reference = 1, default = 1 },
    skin = { values = { 0.1, 0.25, 1, 2 }, reference = 0.5, default = 0.5 },
    dimension = { values = { 3 }, reference = 2, default = 2 },
  },
  quantities = {
    { "restitution", "none" }, { "contact_duration", "time" }, { "max_overlap", "length" },
    { "max_normal_force", "force" }, { "tangential_rebound", "velocity" }, { "spin_after", "spin" },
    { "energy_drift_elastic", "absolute" },
  },
}

local R, RHO, K_REF = 0.2e-3, 1200, 2e4

local function impact(setting, law, angle, spin)
  local d = setting.dimension
  local sim = simulation { dimension = d, steps_per_contact = setting.steps_per_contact, record_contacts = true }
  sim:set { skin = setting.skin * R }
  sim:material { name = "m", density = RHO }
  law[1], law[2] = "m", "m"
  sim:contact(law)
  local function v(x, y) if d == 3 then return { x, y, 0 } end return { x, y } end
  local c, s = math.cos(math.rad(angle)), math.sin(math.rad(angle))
  local gap = 0.01 * R
  local speed = 1.0
  local w = d == 3 and { 0, 0, spin } or spin
  local a = sim:add_particle { position = v(-R - gap / 2, 0), velocity = v(c * speed / 2, s * speed / 2),
                               spin = w, radius = R, material = "m" }
  local b = sim:add_particle { position = v(R + gap / 2, 0), velocity = v(-c * speed / 2, -s * speed / 2),
                               spin = w, radius = R, material = "m" }
  local seen, ended, touching, max_overlap, max_force = false, false, 0, 0, 0
  sim:every { steps = 1, function(q)
    local l = q:contacts()
    if #l == 0 then
      if seen then ended = true end
      return
    end
    seen = true
    if l[1].normal_force > 0 then touching = touching + 1 end
    max_overlap = math.max(max_overlap, l[1].overlap)
    max_force = math.max(max_force, l[1].normal_force)
  end }
  local ke0 = sim:stats().kinetic_energy
  local k = law.k_load or law.k_normal
  local t_c = math.pi * math.sqrt(granule.sphere_mass(R, RHO) / 2 / k)
  sim:run { duration = 50 * t_c, check_every = 1, stop_when = function() return ended end }
  assert(ended, "impact: the contact did not end")
  local pa, pb = sim:particle(a), sim:particle(b)
  local dvx = pb.velocity[1] - pa.velocity[1]
  local dvy = pb.velocity[2] - pa.velocity[2]
  local wa = type(pa.spin) == "table" and pa.spin[3] or pa.spin
  return { restitution = dvx / (c * speed), tangential_rebound = dvy, spin = wa,
           duration = touching * sim:time_step(), max_overlap = max_overlap, max_force = max_force,
           ke_ratio = sim:stats().kinetic_energy / ke0, steps = sim:step_count() }
end

function cases.impact.run(setting)
  local k = K_REF * setting.stiffness
  local wb = { model = "walton_braun", k_load = k, restitution = 0.85, friction = 0.4, tangential_ratio = 0.8 }
  local head = impact(setting, wb, 0, 0)
  local oblique = impact(setting, { model = "walton_braun", k_load = k, restitution = 0.85, friction = 0.4,
                                    tangential_ratio = 0.8 }, 30, 0)
  local elastic = impact(setting, { model = "linear", k_normal = k, restitution = 1 }, 0, 0)
  return { restitution = head.restitution, contact_duration = head.duration, max_overlap = head.max_overlap,
           max_normal_force = head.max_force, tangential_rebound = oblique.tangential_rebound,
           spin_after = oblique.spin, energy_drift_elastic = math.abs(elastic.ke_ratio - 1) },
         head.steps + oblique.steps + elastic.steps
end

-- The Mechanofusion base case (Table 4.1, SPEC 4.1), as scenarios/mechanofusion_demo.lua.
cases.mechanofusion = {
  doc = "2D Mechanofusion base case (Table 4.1)",
  knobs = {
    steps_per_contact = { values = { 10, 20, 40, 80 }, reference = 160, default = 40 },
    stiffness = { values = { 1 / 4, 1 / 16, 1 / 64, 1 / 256, 1 / 1024 }, reference = 1, default = 1 },
    skin = { values = { 0.25, 1, 2 }, reference = 0.5, default = 0.5 },
  },
  quantities = {
    { "inner_normal_force", "force" }, { "inner_tangential_force", "force" },
    { "kinetic_energy", "energy" }, { "max_overlap_ratio", "length" },
    { "normal_force_noise", "absolute" },
    { "inner_normal_force_unscaled", "none" },  -- the same force compared as it is, without Eq. 5.10
    -- Mean normal contact force per particle in each area of 4.4.2 (the areas diagnostic).
    { "area_inner_piece", "force" }, { "area_scraper", "force" }, { "area_input", "force" },
    { "area_free_diffusion", "force" },
  },
}

function cases.mechanofusion.run(setting)
  local k = K_REF * setting.stiffness
  local chamber, inner, gap = 12.5e-3, 5e-3, 1.6e-3
  local sim = simulation { dimension = 2, steps_per_contact = setting.steps_per_contact }
  sim:set { skin = setting.skin * R }
  sim:material { name = "powder", density = RHO }
  sim:material { name = "steel", density = 7800 }
  sim:contact { "powder", "powder", model = "walton_braun", k_load = k, restitution = 0.85, friction = 0.4 }
  sim:contact { "powder", "steel", model = "walton_braun", k_load = k, restitution = 0.85, friction = 0.5 }
  sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = chamber, inside = true,
                      angular_velocity = granule.rpm(p.rpm), material = "steel" }
  sim:wall_cylinder { name = "inner_piece", center = { chamber - gap - inner, 0 }, radius = inner, inside = false,
                      material = "steel" }
  -- The scraper: a row of fixed particles at 100 deg, tilted into the flow, 4.4 mm long.
  local phi, tilt = math.rad(100), math.rad(p.scraper_tilt)
  local outward, tangent = granule.vec.polar(phi), granule.vec.polar(phi + math.pi / 2)
  local first = granule.vec.scale(outward, chamber - R)
  local direction = granule.vec.add(granule.vec.scale(outward, -math.sin(tilt)),
                                    granule.vec.scale(tangent, -math.cos(tilt)))
  for _, x in ipairs(granule.particle_row(first, direction, math.floor(4.4e-3 / (2 * R) + 0.5), R)) do
    sim:add_particle { position = x, radius = R, material = "powder", fixed = true }
  end
  sim:fill { region = { circle = { center = { 0, 0 }, radius = chamber } }, count = p.particles, radius = R,
             material = "powder", seed = 1, max_speed = 0.01 }
  sim:run { duration = p.settle }
  local id = sim:diagnostic("wall_force", { wall = "inner_piece", window = p.average / p.blocks })
  local areas = sim:diagnostic("areas", { window = p.average / p.blocks })
  local ke, samples, overlap = 0, 0, 0
  sim:every { steps = 200, function(q)
    local s = q:stats()
    ke, samples = ke + s.kinetic_energy, samples + 1
    overlap = math.max(overlap, s.max_overlap_ratio)
  end }
  -- Block means of the normal force (from the diagnostic's running mean), for the
  -- noise of the mean: its standard error over the blocks, relative to the mean.
  local block_means, sum_before, n_before = {}, 0, 0
  for _ = 1, p.blocks do
    sim:run { duration = p.average / p.blocks }
    local f = sim:diagnostic_results(id)
    local sum = f.mean_normal_force * f.samples
    block_means[#block_means + 1] = (sum - sum_before) / math.max(f.samples - n_before, 1)
    sum_before, n_before = sum, f.samples
  end
  local f = sim:diagnostic_results(id)
  local mean, var = f.mean_normal_force, 0
  for _, b in ipairs(block_means) do var = var + (b - mean) ^ 2 end
  var = var / math.max(#block_means - 1, 1)
  local noise = math.sqrt(var / #block_means) / math.abs(mean)
  local a = sim:diagnostic_results(areas)
  return { inner_normal_force = f.mean_normal_force, inner_tangential_force = f.mean_tangential_force,
           kinetic_energy = ke / math.max(samples, 1), max_overlap_ratio = overlap,
           normal_force_noise = noise, inner_normal_force_unscaled = f.mean_normal_force,
           area_inner_piece = a.normal_force_per_particle_inner_piece,
           area_scraper = a.normal_force_per_particle_scraper, area_input = a.normal_force_per_particle_input,
           area_free_diffusion = a.normal_force_per_particle_free_diffusion }, sim:step_count()
end

-- A prepared agglomerate on a wall (7.6).
cases.agglomerate = {
  doc = "agglomerate wall impact (7.6)",
  knobs = {
    -- Thornton's laws need n > 16 (their stability limit, T_R / 2 against the rule 8 T_R / n).
    steps_per_contact = { values = { 20, 40, 80 }, reference = 160, default = 40 },
    -- Not a knob: the impact velocity changed by 0.1 %. Breakage is chaotic, so this
    -- row is the noise floor against which the knobs' errors must be read.
    perturbation = { values = { 1.001 }, reference = 1, default = 1 },
  },
  quantities = {
    { "damage_ratio", "none" }, { "debris_ratio", "none" }, { "largest_fraction", "none" },
    { "peak_force", "none" }, { "impact_duration", "none" },
  },
}

function cases.agglomerate.run(setting)
  local tests = require "granule.agglomerate_tests"
  local sim = simulation { dimension = 2, record_contacts = true, steps_per_contact = setting.steps_per_contact }
  local tmp = os.tmpname()
  sim:output { file = tmp }
  local stem = tmp:gsub("%.h5$", "")
  local function clean()
    for _, f in ipairs { tmp, stem .. ".xmf", stem .. "_walls.xmf" } do os.remove(f) end
  end
  local ok, r = pcall(tests.run, sim, "wall", { file = p.file, velocity = p.velocity * setting.perturbation,
                                                quiet = true })
  if not ok then
    pcall(sim.close, sim)
    clean()
    error(r, 0)
  end
  local steps = sim:step_count()
  sim:close()
  clean()
  return { damage_ratio = r.damage_ratio, debris_ratio = r.debris_ratio, largest_fraction = r.largest_fraction,
           peak_force = r.peak_force, impact_duration = r.impact_duration }, steps
end

-- Rolling resistance (contact/rolling.hpp): a sphere rolling without slip on a
-- plane under gravity, from v0 to rest, with each rolling model. The constant
-- torque M = mu_r R N stops it after d = 0.7 v0^2 / (mu_r g) (a solid sphere:
-- 1 + I / (m r^2) = 7/5). The EPSD spring-dashpot (type C) reaches the same
-- limiting torque once its spring has wound up through theta_m = M / k_r; while it
-- winds, its dashpot c = 2 eta_r sqrt(I_r k_r) (I_r = I + m r^2) acts too, but the
-- two together never exceed M: here c w0 is 100 M, so the torque is M from the
-- first step and EPSD stops where the constant torque does (a sphere whose
-- dashpot stays below M while the spring winds goes further, by at most the
-- wind-up's r theta_m / 2).
cases.rolling = {
  doc = "a sphere rolling to rest against rolling friction (0.7 v0^2 / (mu_r g))",
  knobs = {
    steps_per_contact = { values = { 10, 20, 40, 80 }, reference = 320, default = 40 },
    stiffness = { values = { 1 / 4, 1 / 16, 1 / 64 }, reference = 1, default = 1 },
    dimension = { values = { 2 }, reference = 3, default = 3 },
  },
  quantities = {
    { "stop_distance_constant", "none" }, { "stop_distance_epsd", "none" },
    -- |d / d_closed - 1|: against the closed forms above, not the reference run
    { "closed_form_error_constant", "absolute" }, { "closed_form_error_epsd", "absolute" },
  },
}

local ROLL_R, ROLL_RHO, ROLL_K, ROLL_V0, ROLL_MU_R, ROLL_ETA, G = 1e-3, 2500, 1e3, 0.1, 0.1, 0.3, 9.81

local function roll_to_rest(setting, rolling_model)
  local d = setting.dimension
  local sim = simulation { dimension = d, steps_per_contact = setting.steps_per_contact }
  sim:material { name = "ball", density = ROLL_RHO }
  sim:material { name = "floor", density = 0 }
  local k = ROLL_K * setting.stiffness
  for _, other in ipairs { "ball", "floor" } do
    sim:contact { "ball", other, model = "linear", k_normal = k, restitution = 0.5, friction = 0.9,
                  rolling_friction = ROLL_MU_R, rolling_model = rolling_model,
                  rolling_damping = rolling_model == "epsd" and ROLL_ETA or nil }
  end
  local function v(x, y) if d == 3 then return { x, y, 0 } end return { x, y } end
  sim:wall_plane { name = "floor", point = v(0, 0), normal = v(0, 1), material = "floor" }
  sim:gravity(v(0, -G))
  local m = granule.sphere_mass(ROLL_R, ROLL_RHO)
  local w = -ROLL_V0 / ROLL_R
  local id = sim:add_particle { position = v(0, ROLL_R - m * G / k), velocity = v(ROLL_V0, 0),
                                spin = d == 3 and { 0, 0, w } or w, radius = ROLL_R, material = "ball" }
  -- Where it rests: the run lasts 1.4 times the closed form's stopping time 2 d / v0, and
  -- then ten e-folding times of the EPSD rocking (damping ratio 0.3 at the rolling
  -- frequency sqrt(k_r / (I + m r^2)) = mu_r sqrt(2.25 k / (1.4 m))). The first zero of the
  -- speed is no measure: the contact's springs rock the sphere about its resting point.
  local closed = 0.7 * ROLL_V0 ^ 2 / (ROLL_MU_R * G)
  local rocking = ROLL_MU_R * math.sqrt(2.25 * k / (1.4 * m))
  sim:run { duration = 1.4 * 2 * closed / ROLL_V0 + 10 / (ROLL_ETA * rocking) }
  local rest = sim:particle(id)
  assert(math.abs(rest.velocity[1]) < 1e-3 * ROLL_V0, string.format(
    "rolling (%s, %s): still moving at %.3g m/s after %.3g s", rolling_model, setting.steps_per_contact,
    rest.velocity[1], sim:time()))
  local x = rest.position[1]
  return x, math.abs(x / closed - 1), sim:step_count()
end

function cases.rolling.run(setting)
  local dc, ec, nc = roll_to_rest(setting, "constant")
  local de, ee, ne = roll_to_rest(setting, "epsd")
  return { stop_distance_constant = dc, stop_distance_epsd = de, closed_form_error_constant = ec,
           closed_form_error_epsd = ee }, nc + ne
end

-- A parallel bond (contact/parallel_bond.hpp) between two free spheres, in its
-- stretching and twisting modes, against their closed-form periods: axial
-- T = 2 pi sqrt(m / (2 k_n A)), twist T = 2 pi sqrt(I / (2 k_s J)) (two equal spheres:
-- the reduced mass m / 2 and inertia I / 2). The knob steps_per_contact is here the
-- steps per axial period (the time step is set from it); leap-frog's period error is
-- (omega dt)^2 / 24 to leading order.
cases.bond = {
  doc = "a bonded pair's stretching and twisting periods against their closed forms",
  knobs = {
    steps_per_contact = { values = { 10, 20, 40, 80 }, reference = 320, default = 40 },
  },
  quantities = {
    { "axial_period", "none" }, { "twist_period", "none" },
    { "axial_period_error", "absolute" }, { "twist_period_error", "absolute" },
  },
}

function cases.bond.run(setting)
  local r, rho, kn, ks = 1e-3, 2500, 1e12, 4e11
  local m = granule.sphere_mass(r, rho)
  local inertia = 0.4 * m * r * r
  local area, polar = math.pi * r * r, 0.5 * math.pi * r ^ 4
  local axial = 2 * math.pi * math.sqrt(m / (2 * kn * area))
  local twist = 2 * math.pi * math.sqrt(inertia / (2 * ks * polar))
  local sim = simulation { dimension = 3, time_step = axial / setting.steps_per_contact }
  sim:material { name = "ball", density = rho }
  sim:contact { "ball", "ball", model = "linear", k_normal = 1e3, restitution = 1 }
  local gap = 1e-6  -- the spheres never touch: only the bond acts
  local a = sim:add_particle { position = { -r - gap / 2, 0, 0 }, radius = r, material = "ball" }
  local b = sim:add_particle { position = { r + gap / 2, 0, 0 }, radius = r, material = "ball" }
  sim:bond { gap = 2 * gap, normal_stiffness = kn, shear_stiffness = ks, tensile_strength = 1e15, shear_strength = 1e15 }
  -- Stretching: the spheres part at +-v (amplitude v / omega, 1e-8 m, well inside the gap);
  -- twisting: spun about the bond's axis at +-w.
  sim:set_velocity(a, { -0.01, 0, 0 }) sim:set_velocity(b, { 0.01, 0, 0 })
  sim:set_spin(a, { 10, 0, 0 }) sim:set_spin(b, { -10, 0, 0 })
  -- Periods from the upward zero crossings of the relative velocity and spin (linear
  -- interpolation between steps) over 10 axial periods.
  local last = {}
  local crossings = { axial = {}, twist = {} }
  sim:every { steps = 1, function(q)
    local pa, pb = q:particle(a), q:particle(b)
    local now = { axial = pb.velocity[1] - pa.velocity[1], twist = pb.spin[1] - pa.spin[1] }
    for k, v in pairs(now) do
      local before = last[k]
      if before and before < 0 and v >= 0 then
        local t = q:time() - q:time_step() * v / (v - before)
        table.insert(crossings[k], t)
      end
      last[k] = v
    end
  end }
  sim:run { duration = 10.5 * math.max(axial, twist) }
  local function period(list)
    assert(#list >= 3, "bond: too few periods seen")
    return (list[#list] - list[1]) / (#list - 1)
  end
  local ta, tt = period(crossings.axial), period(crossings.twist)
  return { axial_period = ta, twist_period = tt, axial_period_error = math.abs(ta / axial - 1),
           twist_period_error = math.abs(tt / twist - 1) }, sim:step_count()
end

-- ---------------------------------------------------------------------------
local case = cases[p.case]
if not case then error("case must be impact, mechanofusion, agglomerate, rolling or bond, got '" .. tostring(p.case) .. "'") end
local knobs = {}
if p.knob == "all" then
  for _, name in ipairs { "steps_per_contact", "stiffness", "skin", "dimension", "perturbation" } do
    if case.knobs[name] then knobs[#knobs + 1] = name end
  end
  -- Settings are one knob's: given for several, each would be run at the others' values.
  if #knobs > 1 and (p.values ~= "" or p.reference ~= 0) then
    error(string.format("-D values and -D reference are settings of one knob, and case %s has %d "
      .. "(%s): give -D knob=... with them", p.case, #knobs, table.concat(knobs, ", ")), 0)
  end
else
  if not case.knobs[p.knob] then
    local names = {}
    for name in pairs(case.knobs) do names[#names + 1] = name end
    table.sort(names)
    error(string.format("knob '%s' does not apply to case %s (knobs: %s)", p.knob, p.case, table.concat(names, ", ")))
  end
  knobs[1] = p.knob
end

local function default_setting()
  local s = {}
  for name, k in pairs { steps_per_contact = { default = 40 }, stiffness = { default = 1 },
                         skin = { default = 0.5 }, dimension = { default = 2 }, perturbation = { default = 1 } } do
    s[name] = case.knobs[name] and case.knobs[name].default or k.default
  end
  return s
end

-- The K^1/2 law (Eq. 5.10): with K scaled by s, forces scale by s^1/2, times and
-- overlaps by s^-1/2; energies and velocities are unchanged. Brings a run at scale s
-- back to the reference stiffness.
local function rescale(value, kind, scale)
  if kind == "force" then return value / math.sqrt(scale) end
  if kind == "time" or kind == "length" then return value * math.sqrt(scale) end
  return value
end

-- Section 5.4's constraints for the Mechanofusion base case at stiffness K.
local bounds
if p.case == "mechanofusion" then
  local report = kinetic.scaling(kinetic.base_case { rotation_speed_rpm = p.rpm, particle_count = p.particles })
  bounds = { gap = report.k_bound_gap_transit_n_m, collision = report.k_bound_collision_time_n_m }
end

local rows, memo = {}, {}
local function log(...) if not p.quiet then io.stderr:write(string.format(...)) end end
for _, knob in ipairs(knobs) do
  local spec = case.knobs[knob]
  local values = p.values ~= "" and list(p.values) or spec.values
  local reference = p.reference ~= 0 and p.reference or spec.reference
  local settings = { reference }
  for _, v in ipairs(values) do if v ~= reference then settings[#settings + 1] = v end end
  if knob == "steps_per_contact" then
    for _, v in ipairs(settings) do
      if type(v) ~= "number" or v > 1e5 then
        error(string.format("steps_per_contact %s: give a number up to 1e5 (a finer step only costs "
          .. "time: the errors are below round-off long before)", tostring(v)), 0)
      end
    end
  end
  local ref
  for index, value in ipairs(settings) do
    local setting = default_setting()
    setting[knob] = value
    log("accuracy: %s %s = %s ...\n", p.case, knob, tostring(value))
    -- The default setting is every knob's reference but one: run it once.
    local key = string.format("%s|%s|%s|%s|%s", setting.steps_per_contact, setting.stiffness, setting.skin,
      setting.dimension, setting.perturbation)
    local got, steps, seconds
    if memo[key] then
      got, steps, seconds = table.unpack(memo[key])
    else
      local t0 = wall_time()
      got, steps = case.run(setting)
      seconds = wall_time() - t0
      memo[key] = { got, steps, seconds }
    end
    local row = { knob = knob, value = value, reference = index == 1, seconds = seconds, steps = steps,
                  quantities = {} }
    local scale = knob == "stiffness" and value or 1
    for _, q in ipairs(case.quantities) do
      local name, kind = q[1], q[2]
      local v = rescale(got[name], kind, scale)
      row.quantities[name] = v
    end
    if bounds and knob == "stiffness" then
      local k = K_REF * value
      row.margin_5_12, row.margin_5_15 = k / bounds.gap, k / bounds.collision
    end
    if index == 1 then ref = row.quantities end
    row.errors = {}
    for _, q in ipairs(case.quantities) do
      local name, kind = q[1], q[2]
      if kind == "absolute" then
        row.errors[name] = row.quantities[name]
      elseif ref[name] ~= 0 then
        row.errors[name] = math.abs(row.quantities[name] - ref[name]) / math.abs(ref[name])
      else
        row.errors[name] = math.abs(row.quantities[name])
      end
    end
    rows[#rows + 1] = row
  end
end

-- The smoke test's check: leap-frog converges, so the elastic energy drift, which
-- depends smoothly on dt, falls as n grows. The largest force is read at whole
-- steps, within half a step of its maximum: its error is bounded by the sampling
-- error of a sine's peak, 1 - cos(omega dt / 2) ~ (pi / n)^2 / 8 with omega dt
-- about pi / n, here with a factor 2 to spare, and wanders below that bound.
if p.check and p.case == "impact" then
  local by_n = {}
  for _, row in ipairs(rows) do
    if row.knob == "steps_per_contact" and not row.reference then by_n[#by_n + 1] = row end
  end
  table.sort(by_n, function(a, b) return a.value < b.value end)
  assert(#by_n >= 2, "check: give at least two steps_per_contact settings besides the reference")
  for k = 2, #by_n do
    local name = "energy_drift_elastic"
    assert(by_n[k].errors[name] < by_n[k - 1].errors[name], string.format(
      "check: %s error %.3g at n = %s is not below %.3g at n = %s", name, by_n[k].errors[name], by_n[k].value,
      by_n[k - 1].errors[name], by_n[k - 1].value))
  end
  for _, row in ipairs(by_n) do
    local bound = (math.pi / row.value) ^ 2 / 4
    assert(row.errors.max_normal_force <= bound, string.format(
      "check: max_normal_force error %.3g at n = %s is above the sampling bound (pi/n)^2/4 = %.3g",
      row.errors.max_normal_force, row.value, bound))
  end
  print("accuracy: check passed (errors fall as steps_per_contact grows, the peak force within its sampling bound)")
end

-- The rolling smoke test's check: each model stops the sphere within 2 % of its
-- closed form at every setting.
if p.check and p.case == "rolling" then
  for _, row in ipairs(rows) do
    local q = row.quantities
    assert(row.errors.closed_form_error_constant < 0.02, string.format(
      "check: %s = %s: constant-torque distance %.4g m is %.2g off 0.7 v0^2/(mu_r g)", row.knob, row.value,
      q.stop_distance_constant, row.errors.closed_form_error_constant))
    assert(row.errors.closed_form_error_epsd < 0.02, string.format(
      "check: %s = %s: EPSD distance %.4g m is %.2g off its closed form with the wind-up", row.knob, row.value,
      q.stop_distance_epsd, row.errors.closed_form_error_epsd))
  end
  print("accuracy: check passed (rolling distances against 0.7 v0^2 / (mu_r g))")
end

-- The bond smoke test's check: the stretching period's error is leap-frog's own,
-- (omega dt)^2 / 24 with omega dt = 2 pi / n, within 30 %.
if p.check and p.case == "bond" then
  for _, row in ipairs(rows) do
    local expected = (2 * math.pi / row.value) ^ 2 / 24
    assert(math.abs(row.errors.axial_period_error / expected - 1) < 0.3, string.format(
      "check: n = %s: axial period error %.3g, leap-frog's (omega dt)^2/24 is %.3g", row.value,
      row.errors.axial_period_error, expected))
  end
  print("accuracy: check passed (bond periods: leap-frog's error only)")
end

-- Outputs.
local function fmtv(v) return type(v) == "number" and string.format("%.4g", v) or tostring(v) end
local csv_path, md_path = p.out .. "_" .. p.case .. ".csv", p.out .. "_" .. p.case .. ".md"
local csv = assert(io.open(csv_path, "w"))
csv:write("case,knob,setting,is_reference,quantity,value,reference_value,relative_error,wall_time_s,steps,"
  .. "margin_5_12,margin_5_15\n")
local reference_of = {}
for _, row in ipairs(rows) do if row.reference then reference_of[row.knob] = row end end
for _, row in ipairs(rows) do
  for _, q in ipairs(case.quantities) do
    local name = q[1]
    csv:write(string.format("%s,%s,%.6g,%d,%s,%.8g,%.8g,%.6g,%.4f,%d,%s,%s\n", p.case, row.knob, row.value,
      row.reference and 1 or 0, name, row.quantities[name], reference_of[row.knob].quantities[name],
      row.errors[name], row.seconds, row.steps, row.margin_5_12 and string.format("%.4g", row.margin_5_12) or "",
      row.margin_5_15 and string.format("%.4g", row.margin_5_15) or ""))
  end
end
csv:close()

local lines = {}
local function add(s) lines[#lines + 1] = s end
add(string.format("Accuracy against wall time: %s. Errors are relative to the knob's reference setting "
  .. "(marked ref)%s.", case.doc, p.case == "impact" and "; energy_drift_elastic is absolute" or ""))
add("")
local header = { "knob", "setting", "wall time [s]", "steps" }
for _, q in ipairs(case.quantities) do header[#header + 1] = q[1] end
if bounds then header[#header + 1] = "K / bound 5.12, 5.15" end
add("| " .. table.concat(header, " | ") .. " |")
add("|" .. string.rep("---|", #header))
for _, row in ipairs(rows) do
  local cells = { row.knob, fmtv(row.value) .. (row.reference and " (ref)" or ""), string.format("%.2f", row.seconds),
                  tostring(row.steps) }
  for _, q in ipairs(case.quantities) do
    local name = q[1]
    if row.reference then
      cells[#cells + 1] = fmtv(row.quantities[name])
    else
      cells[#cells + 1] = string.format("%.2g", row.errors[name])
    end
  end
  if bounds then
    if row.margin_5_12 then
      local broken = row.margin_5_12 < 1 or row.margin_5_15 < 1
      cells[#cells + 1] = string.format("%.3g, %.3g%s", row.margin_5_12, row.margin_5_15,
        broken and " **broken**" or (row.margin_5_15 < 10 and " (marginal)" or ""))
    else
      cells[#cells + 1] = ""
    end
  end
  add("| " .. table.concat(cells, " | ") .. " |")
end
add("")
add("Reference rows give the values; the other rows give |value - reference| / |reference|"
  .. (p.case == "impact" and " (energy_drift_elastic: |KE_after/KE_before - 1| itself)" or "")
  .. (bounds and "; stiffness rows are rescaled to K = 20000 N/m by the K^1/2 law (Eq. 5.10)" or "") .. ".")
local md = assert(io.open(md_path, "w"))
md:write(table.concat(lines, "\n") .. "\n")
md:close()
print(table.concat(lines, "\n"))
print(string.format("accuracy: wrote %s and %s", csv_path, md_path))
