-- granule.agglomerate: the agglomerate protocols of dissertation chapter 7,
-- written as script logic over the engine's stages and callbacks.
--
--   local agglomerate = require "granule.agglomerate"
--   local report = agglomerate.prepare(sim, { surface_energy = 1.0 })   -- 7.3
--   local result = agglomerate.wall_impact(sim, { velocity = 0.5 })     -- 7.6
--
-- Preparation (7.3): primaries of seven sizes (Fig. 7.9) at random in a circle
-- (2D) or sphere (3D); a centripetal field pulls them together with zero
-- friction and zero surface energy (stage 1); friction and surface energy are
-- switched on as late as possible (stage 2); the field is removed gradually
-- (stage 3). Every stage ends on a stated criterion, with a time cap as a
-- safety net, and the report says which ended it.
--
-- Tests (7.5-7.7): normal impact with a host particle, normal impact on a
-- wall, diametrical compression between two walls. Each samples the damage
-- and debris ratios (7.4) as a time series while it runs, and ends when bond
-- breakage has stopped and the kinetic energy is steady.
--
-- The contact loops and the cluster labelling are C++ (sim:bonds,
-- sim:breakage, src/analysis/breakage.hpp); this file only decides what to run
-- and when to stop. Every number is an option with the dissertation's value
-- as its default; unknown options are errors.
local granule = require "granule"
-- Errors are raised at the first caller outside the library (granule.checks),
-- so that they name the scene's line whether the scene calls a helper itself
-- or through prepare().
local raise = require("granule.checks").raise

local agglomerate = {}

-- ---------------------------------------------------------------------------
-- Materials of chapter 7 (SI units)
-- ---------------------------------------------------------------------------

--- Primary particles, 7.3: "may be considered to be composed of Al2O3".
agglomerate.alumina = { density = 3970, young = 345e9, poisson = 0.26, friction = 0.25 }
--- Host particle, 7.5: PMMA, d = 400 um.
agglomerate.pmma = { density = 1190, young = 3.3e9, poisson = 0.5, friction = 0.30, diameter = 400e-6 }
--- Target wall, 7.6 (density given for completeness: the wall does not move).
agglomerate.target = { density = 6000, young = 1000e9, poisson = 0.45, friction = 0.5 }

-- Options, checks and the random generation (Figs. 7.9-7.10) live in
-- granule.agglomerate_util; they are part of this module's interface.
local util = require "granule.agglomerate_util"
for name, f in pairs(util) do agglomerate[name] = f end
local zero_vector, axis_vector = util.zero_vector, util.axis_vector

-- ---------------------------------------------------------------------------
-- Measures of a set of particles
-- ---------------------------------------------------------------------------

--- Total mass [kg] of the particles `ids`.
function agglomerate.total_mass(sim, ids)
  local m = 0
  for _, id in ipairs(ids) do m = m + sim:particle(id).mass end
  return m
end

--- Centre of mass, mean velocity, mass, outer diameter 2 max(|x - c| + r) and
--- bounding box (low, high) of the particles `ids`.
function agglomerate.geometry(sim, ids)
  local d = sim:dimension()
  local c, v, m = zero_vector(d), zero_vector(d), 0
  local low, high = {}, {}
  for k = 1, d do low[k], high[k] = math.huge, -math.huge end
  local data = {}
  for _, id in ipairs(ids) do
    local p = sim:particle(id)
    data[#data + 1] = p
    m = m + p.mass
    for k = 1, d do
      c[k] = c[k] + p.mass * p.position[k]
      v[k] = v[k] + p.mass * p.velocity[k]
      low[k] = math.min(low[k], p.position[k] - p.radius)
      high[k] = math.max(high[k], p.position[k] + p.radius)
    end
  end
  for k = 1, d do c[k], v[k] = c[k] / m, v[k] / m end
  local reach = 0
  for _, p in ipairs(data) do
    local s = 0
    for k = 1, d do s = s + (p.position[k] - c[k]) ^ 2 end
    reach = math.max(reach, math.sqrt(s) + p.radius)
  end
  return { center = c, velocity = v, mass = m, diameter = 2 * reach, low = low, high = high }
end

--- Contacts among the particles `ids` in the last step: bonds, coordination
--- number 2 bonds / primaries, and how many carry a compressive (N > 0) or a
--- tensile (N < 0) normal force. Needs record_contacts = true.
function agglomerate.contact_census(sim, ids)
  local member = {}
  for _, id in ipairs(ids) do member[id] = true end
  local compressive, tensile, bonds = 0, 0, 0
  for _, c in ipairs(sim:contacts()) do
    if c.b and member[c.a] and member[c.b] then
      bonds = bonds + 1
      if c.normal_force > 0 then
        compressive = compressive + 1
      elseif c.normal_force < 0 then
        tensile = tensile + 1
      end
    end
  end
  return { bonds = bonds, coordination = 2 * bonds / #ids, compressive = compressive, tensile = tensile }
end

--- The rms speed [m/s] of the simulation's particles relative to their centre
--- of mass, sqrt(2 (KE - |P|^2 / 2M) / M) with M their total mass and KE
--- their whole kinetic energy, spin included: a drift of
--- the whole agglomerate is not unrest. Use it while the simulation holds only
--- the agglomerate.
function agglomerate.internal_rms_speed(stats, mass)
  local p2 = 0
  for _, pk in ipairs(stats.momentum) do p2 = p2 + pk * pk end
  return math.sqrt(math.max(0, 2 * (stats.kinetic_energy - p2 / (2 * mass)) / mass))
end

-- ---------------------------------------------------------------------------
-- Stages
-- ---------------------------------------------------------------------------

--- Global damping as a scripted hook: every `every` steps the velocities and
--- spins of `material` are multiplied by exp(-rate every dt), i.e. dv/dt = -rate v.
--- Returns the hook id (sim:remove_hook ends it).
function agglomerate.start_damping(sim, material, rate, every)
  local factor = math.exp(-rate * every * sim:time_step())
  return sim:every { steps = every, name = "global damping", function(s)
    s:scale_velocities { factor = factor, material = material }
  end }
end

--- A stage criterion: the internal rms speed is below `rest_speed` [m/s] and
--- the number of contacts has not changed for `steady_time` [s]. `mass` is the
--- agglomerate's mass; `trace` prints the quantities at every check.
function agglomerate.at_rest(mass, rest_speed, steady_time, trace)
  local last_count, since = -1, 0
  return function(s)
    local st = s:stats()
    if st.contacts_particle ~= last_count then last_count, since = st.contacts_particle, st.time end
    local speed = agglomerate.internal_rms_speed(st, mass)
    if trace then
      io.stderr:write(string.format("  t = %.4e s  internal rms speed %.3e m/s  contacts %d\n", st.time, speed,
        st.contacts_particle))
    end
    return speed < rest_speed and st.time - since >= steady_time
  end
end

--- Runs until `criterion(sim)` holds, checked every `check_every` steps, or
--- until `max_duration` [s] has passed (the safety net). Returns a stage record
--- { name, start, duration, steps, ended_by = "criterion" | "cap" }.
function agglomerate.run_stage(sim, name, max_duration, check_every, criterion, quiet)
  local t0 = sim:time()
  local r = sim:run { duration = max_duration, check_every = check_every, stop_when = criterion }
  local record = { name = name, start = t0, duration = sim:time() - t0, steps = r.steps,
                   ended_by = r.stopped and "criterion" or "cap" }
  if not quiet then
    io.stderr:write(string.format("stage %-24s %9.3f us %9d steps, ended by %s\n", name, record.duration * 1e6,
      record.steps, record.ended_by))
  end
  return record
end

-- ---------------------------------------------------------------------------
-- Preparation protocol (7.3)
-- ---------------------------------------------------------------------------

agglomerate.preparation_defaults = {
  protocol = "dense",              -- a named set of the options below (agglomerate.protocols); given options win
  material = "alumina",            -- name of the primaries' material (declared by prepare)
  density = agglomerate.alumina.density,
  young = agglomerate.alumina.young,
  poisson = agglomerate.alumina.poisson,
  friction = agglomerate.alumina.friction,
  surface_energy = 1.0,            -- Gamma [J/m^2]; 7.3 uses 1.0 and 2.0
  count = 217,                     -- primaries (7.3)
  mean_diameter = 5e-6,            -- m (7.3)
  size_spread = 0.05,              -- +- 5 % (7.3, Fig. 7.9)
  size_classes = 7,                -- (7.3)
  generation_diameter = 0,         -- m; 0: 100 um in 2D (7.3); in 3D the sphere the primaries fill to 25 %
  center = false,                  -- {x, y[, z]}; false: the origin
  seed = 1,                        -- math.randomseed for sizes and positions
  clearance = 0.02,                -- gap a generation push leaves between a pair, fraction of r_i + r_j (later pushes may close it)
  field_strength = 5e5,            -- m/s^2 toward the centre: the "centripetal gravity field"
  damping_rate = 1e6,              -- 1/s: global damping dv/dt = -c v, during preparation only
  damping_every = 10,              -- steps between velocity scalings
  rest_speed = 1e-4,               -- m/s: at rest when the internal rms speed is below this
  steady_time = 2e-6,              -- s: ... and the contact count has not changed for this long
  compaction_friction = 0,         -- mu during stage 1 (7.3: zero, "to obtain a dense agglomerate")
  compaction_surface_energy = 0,   -- Gamma [J/m^2] during stage 1 (7.3: zero)
  switch_order = "together",       -- stage 2: "together", "friction_first" or "adhesion_first" (each to rest)
  surface_energy_steps = 1,        -- stage 2 raises Gamma to its value in this many equal steps, each to rest
  field_decrements = 10,           -- stage 3 lowers the field in this many equal steps
  decrement_duration = 0,          -- s per decrement; 0: each decrement until rest (else a linear ramp at this rate)
  check_every = 200,               -- steps between checks of the stage criteria
  stage1_max_duration = 400e-6,    -- s: caps, a safety net only
  stage2_max_duration = 100e-6,    -- s
  decrement_max_duration = 40e-6,  -- s, per decrement of stage 3
  quiet_duration = 20e-6,          -- s: final run with neither field nor damping
  snapshot_generated = false,      -- write a snapshot of the random start (Fig. 7.10); needs sim:output
  quiet = false,                   -- no progress lines on stderr
  trace = false,                   -- print the criterion's quantities at every check
}

--- Named preparation protocols: option sets that prepare { protocol = name }
--- starts from. "dense" is 7.3 read literally (zero friction and adhesion
--- while the field compacts, both switched on once the packing is at rest);
--- "sticky" has friction and adhesion on from the first contact, so that
--- primaries stick where they meet (the loosest reading, the one that could
--- give a tree of N - 1 bonds).
agglomerate.protocols = {
  dense = {},
  sticky = { compaction_friction = "friction", compaction_surface_energy = "surface_energy" },
}

local preparation_rules = {
  density = { "positive", "kg/m^3" }, young = { "positive", "Pa" }, poisson = { "non_negative" },
  friction = { "non_negative" }, surface_energy = { "non_negative", "J/m^2" }, count = { "count" },
  mean_diameter = { "positive", "m" }, size_spread = { "non_negative" }, size_classes = { "count" },
  generation_diameter = { "non_negative", "m" }, seed = { "non_negative" }, clearance = { "non_negative" },
  field_strength = { "positive", "m/s^2" }, damping_rate = { "positive", "1/s" }, damping_every = { "count" },
  rest_speed = { "positive", "m/s" }, steady_time = { "non_negative", "s" }, field_decrements = { "count" },
  check_every = { "count" }, stage1_max_duration = { "positive", "s" }, stage2_max_duration = { "positive", "s" },
  decrement_max_duration = { "positive", "s" }, quiet_duration = { "non_negative", "s" },
  compaction_friction = { "non_negative" }, compaction_surface_energy = { "non_negative", "J/m^2" },
  surface_energy_steps = { "count" }, decrement_duration = { "non_negative", "s" },
}

--- Prepares an agglomerate in `sim` (no particles yet, record_contacts = true)
--- by the protocol of 7.3, declaring the primaries' material and its
--- thornton_jkr self-contact. Returns a report: the primaries' ids, each
--- stage with what ended it, and at the end the diameter, bonds, coordination
--- number and the compressive and tensile contacts (7.3: "about as many").
function agglomerate.prepare(sim, given)
  local context = "agglomerate.prepare"
  local o = agglomerate.options(given, agglomerate.preparation_defaults, context)
  local preset = agglomerate.protocols[o.protocol]
  if not preset then
    local names = {}
    for name in pairs(agglomerate.protocols) do names[#names + 1] = name end
    table.sort(names)
    raise(string.format("%s: unknown protocol '%s' (%s)", context, tostring(o.protocol), table.concat(names, ", ")))
  end
  for k, v in pairs(preset) do
    if given == nil or given[k] == nil then o[k] = v end
  end
  if o.compaction_surface_energy == "surface_energy" then o.compaction_surface_energy = o.surface_energy end
  if o.compaction_friction == "friction" then o.compaction_friction = o.friction end
  agglomerate.check(o, preparation_rules, context)
  local orders = { together = true, friction_first = true, adhesion_first = true }
  if not orders[o.switch_order] then
    raise(string.format("%s: 'switch_order' must be \"together\", \"friction_first\" or \"adhesion_first\", got %s",
      context, tostring(o.switch_order)))
  end
  local d = sim:dimension()
  if #sim:particles() > 0 then error(context .. ": the simulation must hold no particles yet", 2) end
  local center = o.center or zero_vector(d)

  -- Generation (Figs. 7.9-7.10): sizes, then random positions without overlaps.
  local seed = math.tointeger(o.seed)
  if not seed then error(context .. ": 'seed' must be a whole number, got " .. tostring(o.seed), 2) end
  -- Before a list of `count` sizes is built: more primaries than a given region
  -- takes (random_positions' check, from the equal counts per size class), or a
  -- count the generation (a Lua table per primary) cannot hold.
  local classes = agglomerate.size_classes(o.mean_diameter, o.size_spread, o.size_classes)
  if o.generation_diameter > 0 or d == 2 then
    local expected = 0
    for c, dc in ipairs(classes) do
      local n = o.count // #classes + (c <= o.count % #classes and 1 or 0)
      expected = expected + n * (d == 2 and math.pi * (dc / 2) ^ 2 or 4 / 3 * math.pi * (dc / 2) ^ 3)
    end
    local given = o.generation_diameter > 0 and o.generation_diameter or 100e-6
    agglomerate.check_fill(d, given / 2, o.count, expected, context)
  end
  if o.count > 1e6 then raise(string.format("%s: 'count' must be at most 1e6, got %.6g", context, o.count)) end
  math.randomseed(seed)
  local diameters = agglomerate.primary_diameters(o.count, classes)
  local radii, solid = {}, 0
  for k, dk in ipairs(diameters) do
    radii[k] = dk / 2
    solid = solid + (d == 2 and math.pi * radii[k] ^ 2 or 4 / 3 * math.pi * radii[k] ^ 3)
  end
  local region_diameter = o.generation_diameter
  if region_diameter == 0 then
    region_diameter = d == 2 and 100e-6 or 2 * (3 * solid / (0.25 * 4 * math.pi)) ^ (1 / 3)
  end
  local positions, sweeps = agglomerate.random_positions(d, center, region_diameter / 2, radii, o.clearance, 5000)
  sim:material { name = o.material, density = o.density, young = o.young, poisson = o.poisson }
  -- Stage 1's law: Thornton's with mu = 0 and Gamma = 0 (7.3), i.e. frictionless
  -- Hertz, unless the protocol compacts with friction or adhesion on.
  sim:contact { o.material, o.material, model = "thornton_jkr", friction = o.compaction_friction,
                surface_energy = o.compaction_surface_energy }
  local ids = {}
  for k = 1, o.count do ids[k] = sim:add_particle { position = positions[k], radius = radii[k], material = o.material } end
  if o.snapshot_generated then sim:snapshot() end
  local mass = agglomerate.total_mass(sim, ids)
  local report = { ids = ids, stages = {}, count = o.count, mass = mass, generation_diameter = region_diameter,
                   relaxation_sweeps = sweeps, surface_energy = o.surface_energy, friction = o.friction,
                   material = o.material, options = o, solid = solid, dimension = d }
  local rest = function() return agglomerate.at_rest(mass, o.rest_speed, o.steady_time, o.trace) end

  -- Thornton's law with mu = Gamma = 0 dissipates nothing: without damping the
  -- pulled-in primaries would oscillate for ever. Global damping (as in
  -- Thornton's preparations) is on for the three stages and off afterwards.
  local damping = agglomerate.start_damping(sim, o.material, o.damping_rate, o.damping_every)

  -- Stage 1: the centripetal field pulls the primaries together; frictionless and
  -- without adhesion they slide into a dense packing.
  sim:central_field { point = center, strength = o.field_strength }
  report.stages[1] = agglomerate.run_stage(sim, string.format("1 field, mu = %g, Gamma = %g", o.compaction_friction,
    o.compaction_surface_energy), o.stage1_max_duration, o.check_every, rest(), o.quiet)

  -- Stage 2: friction and surface energy switched on as late as possible: now,
  -- with the packing at rest under the field. In one go, or one after the
  -- other, Gamma in `surface_energy_steps` equal steps; each change to rest.
  local steps = {}
  local gamma0 = o.compaction_surface_energy
  local function gamma_steps(mu)
    for k = 1, o.surface_energy_steps do
      steps[#steps + 1] = { friction = mu, surface_energy = gamma0 + (o.surface_energy - gamma0) * k / o.surface_energy_steps }
    end
  end
  if o.switch_order == "friction_first" then
    steps[1] = { friction = o.friction, surface_energy = gamma0 }
    gamma_steps(o.friction)
  elseif o.switch_order == "adhesion_first" then
    gamma_steps(o.compaction_friction)
    steps[#steps + 1] = { friction = o.friction, surface_energy = o.surface_energy }
  else
    gamma_steps(o.friction)
  end
  local stage2 = { name = "2 mu and Gamma on", start = sim:time(), steps = 0, ended_by = "criterion" }
  for _, law in ipairs(steps) do
    sim:set_contact(o.material, o.material, law)
    local r = agglomerate.run_stage(sim, "2 mu and Gamma on", o.stage2_max_duration, o.check_every, rest(), true)
    stage2.steps = stage2.steps + r.steps
    if r.ended_by == "cap" then stage2.ended_by = "cap" end
  end
  stage2.duration = sim:time() - stage2.start
  report.stages[2] = stage2
  if not o.quiet then
    io.stderr:write(string.format("stage %-24s %9.3f us %9d steps, ended by %s\n", stage2.name, stage2.duration * 1e6,
      stage2.steps, stage2.ended_by))
  end

  -- Stage 3: the field removed in equal decrements, each followed by a return to
  -- rest, so the agglomerate stays in equilibrium; or, with a decrement_duration,
  -- as a linear ramp to zero at the same mean rate, set in C++ before every step.
  local stage3 = { name = "3 field removed", start = sim:time(), steps = 0,
                   ended_by = o.decrement_duration > 0 and "duration" or "criterion", decrements = {} }
  local ramp_end = stage3.start + o.field_decrements * o.decrement_duration
  if o.decrement_duration > 0 then
    sim:schedule { "central_strength", linear = { stage3.start, o.field_strength, ramp_end, 0 } }
  end
  for k = 1, o.field_decrements do
    local strength = o.field_strength * (1 - k / o.field_decrements)
    local r
    if o.decrement_duration > 0 then  -- the ramp's k-th part: a fixed time, rest or not
      r = agglomerate.run_stage(sim, string.format("3.%d field to %.3g m/s^2", k, strength), o.decrement_duration,
        o.check_every, function() return false end, true)
      r.ended_by = "duration"  -- a fixed time: no rest was asked for, none is claimed
    else
      if k == o.field_decrements then sim:remove_central_field() else sim:set_central_strength(strength) end
      r = agglomerate.run_stage(sim, string.format("3.%d field %.3g m/s^2", k, strength),
        o.decrement_max_duration, o.check_every, rest(), true)
    end
    stage3.steps = stage3.steps + r.steps
    stage3.decrements[k] = r
    if r.ended_by == "cap" then stage3.ended_by = "cap" end
  end
  if o.decrement_duration > 0 then sim:remove_central_field() end  -- the ramp's end (held at 0 after it)
  stage3.duration = sim:time() - stage3.start
  report.stages[3] = stage3
  if not o.quiet then
    io.stderr:write(string.format("stage %-24s %9.3f us %9d steps, ended by %s%s\n", stage3.name,
      stage3.duration * 1e6, stage3.steps, stage3.ended_by,
      stage3.ended_by == "cap" and " (in at least one decrement)" or ""))
  end
  sim:remove_hook(damping)

  -- Quiet run, neither field nor damping: an agglomerate in equilibrium stays at
  -- rest and keeps its bonds.
  local bonds_before = #sim:bonds { material = o.material }
  local peak = 0
  local probe = sim:every { steps = o.check_every, name = "quiet check", function(s)
    peak = math.max(peak, agglomerate.internal_rms_speed(s:stats(), mass))
  end }
  if o.quiet_duration > 0 then sim:run { duration = o.quiet_duration } end
  sim:remove_hook(probe)

  local census = agglomerate.contact_census(sim, ids)
  local shape = agglomerate.geometry(sim, ids)
  report.quiet = { duration = o.quiet_duration, peak_rms_speed = peak, bonds_before = bonds_before,
                   bonds_after = census.bonds }
  report.diameter, report.center = shape.diameter, shape.center
  -- Solids over the circle (sphere) of the outer diameter.
  local enclosed = d == 2 and math.pi * (shape.diameter / 2) ^ 2 or 4 / 3 * math.pi * (shape.diameter / 2) ^ 3
  report.packing_fraction = solid / enclosed
  report.bonds, report.coordination = census.bonds, census.coordination
  if census.bonds == 0 then
    io.stderr:write("warning: agglomerate.prepare: the prepared agglomerate holds no contacts between its "
      .. "primaries (surface_energy = 0 holds nothing together): its primaries are loose, and a breakage "
      .. "test on it reads damage 0\n")
  end
  report.compressive, report.tensile = census.compressive, census.tensile
  report.rms_speed = agglomerate.internal_rms_speed(sim:stats(), mass)
  report.time = sim:time()
  return report
end

--- Writes the prepared agglomerate to the simulation's output file `path`: a
--- last snapshot, then (the output closed) the contact histories of the same
--- step (sim:save_contact_histories), which sim:load_particles restores with
--- it. Returns the number of histories saved.
function agglomerate.save(sim, path, report)
  sim:snapshot()
  sim:close()
  return sim:save_contact_histories { file = path, material = report.material }
end

--- One line "key=value ..." summarising a preparation report.
function agglomerate.preparation_line(report)
  local ended = {}
  for k, stage in ipairs(report.stages) do ended[k] = stage.ended_by end
  return granule.summary_line({
    primaries = report.count, diameter_m = report.diameter, bonds = report.bonds,
    coordination = report.coordination, compressive = report.compressive, tensile = report.tensile,
    rms_speed_m_s = report.rms_speed, quiet_peak_rms_speed_m_s = report.quiet.peak_rms_speed,
    quiet_bonds_lost = report.quiet.bonds_before - report.quiet.bonds_after,
    stages_ended_by = table.concat(ended, ","), prepared_in_s = report.time,
  }, { "primaries", "diameter_m", "bonds", "coordination", "compressive", "tensile", "rms_speed_m_s",
       "quiet_peak_rms_speed_m_s", "quiet_bonds_lost", "stages_ended_by", "prepared_in_s" })
end

--- Writes a preparation report into the simulation's output: the series
--- /preparation (a row per stage: stage, start_time, duration, steps,
--- criterion_met = 1 if the criterion ended it, 0 if the cap did or, for a
--- stage 3 ramp, its fixed duration) and the
--- /results attributes.
function agglomerate.write_preparation(sim, report)
  sim:series("preparation", { "stage", "start_time", "duration", "steps", "criterion_met" },
             { "-", "s", "s", "-", "-" })
  for k, stage in ipairs(report.stages) do
    sim:append("preparation", { k, stage.start, stage.duration, stage.steps, stage.ended_by == "criterion" and 1 or 0 })
  end
  sim:result {
    primaries = report.count, diameter = report.diameter, bonds = report.bonds, coordination = report.coordination,
    compressive_contacts = report.compressive, tensile_contacts = report.tensile, rms_speed = report.rms_speed,
    quiet_peak_rms_speed = report.quiet.peak_rms_speed,
    quiet_bonds_lost = report.quiet.bonds_before - report.quiet.bonds_after,
    generation_diameter = report.generation_diameter, mass = report.mass, surface_energy = report.surface_energy,
    friction = report.friction, prepared_in = report.time, packing_fraction = report.packing_fraction,
    compaction_friction = report.options.compaction_friction,
    compaction_surface_energy = report.options.compaction_surface_energy,
    field_strength = report.options.field_strength, damping_rate = report.options.damping_rate,
    field_decrements = report.options.field_decrements, decrement_duration = report.options.decrement_duration,
    surface_energy_steps = report.options.surface_energy_steps,
    stage1_duration = report.stages[1].duration, stage2_duration = report.stages[2].duration,
    stage3_duration = report.stages[3].duration,
    stages_by_criterion = (report.stages[1].ended_by == "criterion" and 1 or 0)
      + (report.stages[2].ended_by == "criterion" and 1 or 0) + (report.stages[3].ended_by == "criterion" and 1 or 0),
  }
end

return agglomerate
