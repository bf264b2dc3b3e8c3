-- The DEM verification benchmarks of Chung and Ooi (Granular Matter 13, 643-656,
-- 2011), as users of Yade, LIGGGHTS or Kratos run them on a new code, each
-- result beside its closed form where one exists:
--   Test 1: two identical spheres (r = 10 mm, glass and limestone) head-on at
--           10 m/s each, elastic: peak force, largest overlap and contact time
--           against Hertz's solution;
--   Test 2: a sphere (r = 2.5 mm, aluminium and magnesium alloys) normally onto
--           a plane at 0.2 m/s, elastic: the same;
--   Test 3: the same plane at 3.9 m/s with restitution e from 0.1 to 0.9
--           (aluminium oxide and cast iron): the rebound against e;
--   Test 4: an aluminium oxide sphere (mu = 0.092) onto the plane at 3.9 m/s,
--           incidence angles 5-85 degrees from the normal: tangential
--           restitution e_t = v_t'/v_t, the spin after, and the contact patch's
--           rebound angle; where the contact slides throughout (tan theta >=
--           3.5 mu (1 + e)) the impulse mu (1 + e) m v_n gives them in closed
--           form: e_t = 1 - mu (1 + e) / tan theta, omega = 5 mu (1 + e) v_n / (2 r).
-- The plane is a wall `wall_stiffness` times stiffer than the sphere (Young's
-- modulus; the same Poisson ratio), as the benchmark's "rigid" plane is usually
-- made; the closed forms use that wall's E*. Each impact runs in a simulation of
-- its own until the contact ends. Prints a Markdown table per test and writes
-- <out>_test<N>.csv; with -D check=1 a closed form missed by more than the
-- discretisation allows stops the scene (the test suite runs it so).
--
--   granule run scenarios/chung_ooi.lua -q     (-q: no run header for each impact)
--   granule run scenarios/chung_ooi.lua -q -D tests=4 -D steps_per_contact=640
--   /usr/bin/python3 tools/plot_chung_ooi.py chung_ooi_test4.csv
local p = parameters {
  tests = { default = "1,2,3,4", doc = "comma-separated benchmark numbers (1-4)" },
  models = { default = "hertz_mindlin,thornton_elastic", doc = "comma-separated laws: hertz_mindlin (damped Hertz-Mindlin; e from restitution) | thornton_elastic (Mindlin-Deresiewicz, elastic)" },
  steps_per_contact = { default = 40, above = 0, unit = "-", doc = "n of the time-step rule (8 T_R / n for Hertz's laws)" },
  angles = { default = "5,10,15,20,25,30,35,40,45,50,60,70,80,85", unit = "deg", doc = "Test 4: comma-separated incidence angles from the normal" },
  restitutions = { default = "0.1,0.3,0.5,0.7,0.9", unit = "-", doc = "Test 3: comma-separated restitution coefficients (hertz_mindlin)" },
  friction = { default = 0.092, min = 0, unit = "-", doc = "Test 4: the sphere's friction against the plane" },
  wall_stiffness = { default = 1000, above = 1, unit = "-", doc = "the plane's Young's modulus over the sphere's" },
  shrink_rescale = { default = 0, integer = true, min = 0, max = 1, unit = "-", doc = "1: the tangential spring scales with the contact radius while the overlap falls (both laws; docs/contact_models.md)" },
  out = { default = "chung_ooi", doc = "prefix of the CSV files" },
  check = { default = 0, integer = true, min = 0, max = 1, unit = "-", doc = "1: stop on a closed form missed (Tests 1, 2, 3 and 4's sliding rows)" },
}

local function list(text, what)
  local values = {}
  for item in string.gmatch(text, "[^,]+") do
    values[#values + 1] = tonumber(item) or item:match("^%s*(.-)%s*$")
  end
  if #values == 0 then error(string.format("-D %s: give at least one value", what), 0) end
  return values
end

-- Chung and Ooi's materials (their Tables 1-4).
local materials = {
  glass = { young = 4.8e10, poisson = 0.20, density = 2800 },
  limestone = { young = 2.0e10, poisson = 0.25, density = 2500 },
  aluminium_alloy = { young = 7.0e10, poisson = 0.33, density = 2700 },
  magnesium_alloy = { young = 4.0e10, poisson = 0.35, density = 1800 },
  aluminium_oxide = { young = 3.8e11, poisson = 0.23, density = 4000 },
  cast_iron = { young = 1.0e11, poisson = 0.25, density = 7000 },
}

local function sphere_mass(m, r) return m.density * 4 / 3 * math.pi * r ^ 3 end
-- E* of two bodies (1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2).
local function reduced_young(a, b) return 1 / ((1 - a.poisson ^ 2) / a.young + (1 - b.poisson ^ 2) / b.young) end
-- Hertz's elastic impact at closing speed v: largest overlap, peak force, contact time.
local function hertz(m_eff, r_eff, e_star, v)
  local overlap = (15 * m_eff * v * v / (16 * e_star * math.sqrt(r_eff))) ^ 0.4
  local force = 4 / 3 * e_star * math.sqrt(r_eff) * overlap ^ 1.5
  local time = 2.868265 * (m_eff * m_eff / (r_eff * e_star * e_star * v)) ^ 0.2
  return overlap, force, time
end

local function law(model, restitution, friction)
  if model == "hertz_mindlin" then
    return { model = model, restitution = restitution, friction = friction, shrink_rescale = p.shrink_rescale }
  elseif model == "thornton_elastic" then
    if restitution < 1 then return nil end  -- elastic only
    return { model = model, friction = friction, shrink_rescale = p.shrink_rescale }
  end
  error(string.format("-D models: unknown law '%s' (hertz_mindlin or thornton_elastic)", tostring(model)), 0)
end

-- One impact in a simulation of its own: sphere a (material `ma`, radius r) at
-- velocity {v_t, 0, -v_n} onto a plane at z = 0 (wall = true) or onto sphere b
-- of the same kind coming up at the same speed. Returns what the contact did.
local function impact(o)
  local sim = simulation { dimension = 3, steps_per_contact = p.steps_per_contact, record_contacts = true }
  sim:material { name = "sphere", density = o.material.density, young = o.material.young, poisson = o.material.poisson }
  sim:material { name = "plane", density = 0, young = o.material.young * p.wall_stiffness, poisson = o.material.poisson }
  for _, other in ipairs { "sphere", "plane" } do
    local c = law(o.model, o.restitution, o.friction)
    c[1], c[2] = "sphere", other
    sim:contact(c)
  end
  local r = o.radius
  -- A gap of 1e-3 r: closed within a few steps, so the approach turns nothing.
  local gap = 1e-3 * r
  local a, b
  if o.wall then
    sim:wall_plane { name = "plane", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "plane" }
    a = sim:add_particle { position = { 0, 0, r + gap }, radius = r, material = "sphere",
                           velocity = { o.v_t, 0, -o.v_n } }
  else
    a = sim:add_particle { position = { 0, 0, r + gap / 2 }, radius = r, material = "sphere", velocity = { 0, 0, -o.v_n } }
    b = sim:add_particle { position = { 0, 0, -r - gap / 2 }, radius = r, material = "sphere", velocity = { 0, 0, o.v_n } }
  end
  local energy = function()
    local s = sim:stats()
    return s.kinetic_energy_translational + s.kinetic_energy_rotational
  end
  local before = energy()
  local seen, ended, steps, peak_force, peak_overlap = false, false, 0, 0, 0
  sim:every { steps = 1, function(s)
    local c = s:contacts()[1]
    if not c then
      ended = seen
      return
    end
    seen = true
    steps = steps + 1
    peak_force = math.max(peak_force, c.normal_force)
    peak_overlap = math.max(peak_overlap, c.overlap)
  end }
  -- Far longer than any contact here: a contact still going on is an error below.
  sim:run { duration = 1e-3, check_every = 1, stop_when = function() return ended end }
  if not ended then error(string.format("Test %d: the contact did not end within 1 ms", o.test), 0) end
  local pa = sim:particle(a)
  local result = {
    force = peak_force, overlap = peak_overlap, time = steps * sim:time_step(), dt = sim:time_step(),
    v_t = pa.velocity[1], v_n = pa.velocity[3], spin = pa.spin[2], energy_ratio = energy() / before,
  }
  return result
end

local csv_files = {}
local function csv(test, header, row)
  local name = string.format("%s_test%d.csv", p.out, test)
  local f = csv_files[name]
  if not f then
    f = assert(io.open(name, "w"))
    f:write(header, "\n")
    csv_files[name] = f
  end
  f:write(row, "\n")
end
local missed = {}
local function expect(what, value, reference, tolerance)
  local error_rel = math.abs(value / reference - 1)
  if p.check == 1 and not (error_rel <= tolerance) then
    missed[#missed + 1] = string.format("%s: %.6g against %.6g (%.2g, more than %.2g)", what, value, reference,
                                        error_rel, tolerance)
  end
  return error_rel
end
-- The discretisation's bound at n steps per contact: 1 % at n = 40, as n^-2 after.
local n = p.steps_per_contact
local peak_tolerance = math.max(1e-4, 0.01 * (40 / n) ^ 2)

local tests = {}
for _, t in ipairs(list(p.tests, "tests")) do
  if t ~= 1 and t ~= 2 and t ~= 3 and t ~= 4 then
    error(string.format("-D tests: unknown benchmark '%s' (1, 2, 3 or 4)", tostring(t)), 0)
  end
  tests[t] = true
end
local models = list(p.models, "models")
for _, model in ipairs(models) do law(model, 1, 0) end
-- Test 3 needs a law for each restitution asked (thornton_elastic is elastic: e = 1
-- only): refused before any test runs, not half-way.
if tests[3] then
  for _, e in ipairs(list(p.restitutions, "restitutions")) do
    if not (type(e) == "number" and e > 0 and e <= 1) then
      error(string.format("-D restitutions: %s is not in (0, 1]", tostring(e)), 0)
    end
    local any = false
    for _, model in ipairs(models) do any = any or law(model, e, 0) ~= nil end
    if not any then
      error(string.format("Test 3 (in -D tests) at restitution %g: no law of -D models gives it "
        .. "(thornton_elastic is elastic); add hertz_mindlin", e), 0)
    end
  end
end

local function normal_test(test, pair, cases, speed, radius)
  print(string.format("\n## Test %d: %s, r = %g m, %g m/s%s (n = %g)\n", test,
                      pair and "two spheres head-on" or "a sphere onto the plane", radius, speed,
                      pair and " each" or "", n))
  print("| material | law | peak force [N] | closed form | max overlap [m] | closed form | contact time [s] | closed form | rebound / approach |")
  print("|---|---|---|---|---|---|---|---|---|")
  for _, name in ipairs(cases) do
    local m = materials[name]
    local plane = { young = m.young * p.wall_stiffness, poisson = m.poisson }
    local e_star = pair and reduced_young(m, m) or reduced_young(m, plane)
    local mass = sphere_mass(m, radius)
    local m_eff, r_eff = pair and mass / 2 or mass, pair and radius / 2 or radius
    local v = pair and 2 * speed or speed
    local overlap, force, time = hertz(m_eff, r_eff, e_star, v)
    for _, model in ipairs(models) do
      local r = impact { test = test, material = m, model = model, restitution = 1, friction = 0.35,
                         radius = radius, wall = not pair, v_t = 0, v_n = speed }
      local rebound = r.v_n / speed  -- sphere a leaves upwards, in both set-ups
      print(string.format("| %s | %s | %.6g | %.6g | %.6g | %.6g | %.5g | %.5g | %.6f |", name, model, r.force,
                          force, r.overlap, overlap, r.time, time, rebound))
      csv(test, "material,model,steps_per_contact,peak_force_N,peak_force_closed_N,max_overlap_m,max_overlap_closed_m,contact_time_s,contact_time_closed_s,rebound_ratio",
          string.format("%s,%s,%g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g", name, model, n, r.force, force,
                        r.overlap, overlap, r.time, time, rebound))
      local what = string.format("Test %d %s %s", test, name, model)
      expect(what .. " peak force", r.force, force, peak_tolerance)
      expect(what .. " max overlap", r.overlap, overlap, peak_tolerance)
      -- A count of steps: within two steps of the closed form.
      expect(what .. " contact time", r.time, time, 2 * r.dt / time + 1e-3)
      expect(what .. " rebound", rebound, 1, peak_tolerance)
    end
  end
end

if tests[1] then normal_test(1, true, { "glass", "limestone" }, 10, 0.010) end
if tests[2] then normal_test(2, false, { "aluminium_alloy", "magnesium_alloy" }, 0.2, 0.0025) end

if tests[3] then
  print(string.format("\n## Test 3: restitution of a sphere (r = 2.5 mm) onto the plane at 3.9 m/s (n = %g)\n", n))
  print("| material | law | e given | rebound / approach | relative difference |")
  print("|---|---|---|---|---|")
  for _, name in ipairs { "aluminium_oxide", "cast_iron" } do
    for _, e in ipairs(list(p.restitutions, "restitutions")) do  -- checked before any test
      for _, model in ipairs(models) do
        if law(model, e, 0) then
          local r = impact { test = 3, material = materials[name], model = model, restitution = e, friction = 0,
                             radius = 0.0025, wall = true, v_t = 0, v_n = 3.9 }
          local rebound = r.v_n / 3.9
          local difference = expect(string.format("Test 3 %s %s e = %g", name, model, e), rebound, e,
                                    math.max(2e-3, 0.07 * 40 / n))  -- first order in the step
          print(string.format("| %s | %s | %g | %.5f | %.2g |", name, model, e, rebound, difference))
          csv(3, "material,model,steps_per_contact,restitution,rebound_ratio",
              string.format("%s,%s,%g,%g,%.10g", name, model, n, e, rebound))
        end
      end
    end
  end
end

if tests[4] then
  local m, r, speed, mu = materials.aluminium_oxide, 0.0025, 3.9, p.friction
  print(string.format("\n## Test 4: aluminium oxide sphere (r = 2.5 mm, mu = %g) onto the plane at %g m/s (n = %g)\n",
                      mu, speed, n))
  print("e_t = v_t'/v_t; e_t,patch = (v_t' - r omega')/v_t; omega' the spin after (rolling sense +); theta' the")
  print("contact patch's rebound angle; closed forms where the contact slides throughout.\n")
  print("| angle [deg] | law | e_t | closed form | omega' [rad/s] | closed form | e_t,patch | theta' [deg] | energy after / before |")
  print("|---|---|---|---|---|---|---|---|---|")
  for _, angle in ipairs(list(p.angles, "angles")) do
    if not (type(angle) == "number" and angle > 0 and angle < 90) then
      error(string.format("-D angles: %s is not in (0, 90) degrees", tostring(angle)), 0)
    end
    local v_t, v_n = speed * math.sin(math.rad(angle)), speed * math.cos(math.rad(angle))
    for _, model in ipairs(models) do
      local res = impact { test = 4, material = m, model = model, restitution = 1, friction = mu, radius = r,
                           wall = true, v_t = v_t, v_n = v_n }
      local e_n = res.v_n / v_n
      local e_t = res.v_t / v_t
      local patch = (res.v_t - r * res.spin) / v_t
      local rebound_angle = math.deg(math.atan(res.v_t - r * res.spin, res.v_n))
      local sliding = math.tan(math.rad(angle)) >= 3.5 * mu * (1 + e_n)
      local closed_e_t = sliding and 1 - mu * (1 + e_n) / math.tan(math.rad(angle)) or nil
      local closed_spin = sliding and 5 * mu * (1 + e_n) * v_n / (2 * r) or nil
      if sliding then
        local what = string.format("Test 4 %g deg %s", angle, model)
        expect(what .. " e_t", e_t, closed_e_t, 1e-4)
        -- The wall's lever is r - a/2 .. r - a, not r: a fraction of a per cent.
        expect(what .. " spin", res.spin, closed_spin, 5e-3)
      end
      local function shown(x, format) return x and string.format(format, x) or "-" end
      print(string.format("| %g | %s | %.5f | %s | %.2f | %s | %+.5f | %+.3f | %.5f |", angle, model, e_t,
                          shown(closed_e_t, "%.5f"), res.spin, shown(closed_spin, "%.2f"), patch, rebound_angle,
                          res.energy_ratio))
      csv(4, "angle_deg,model,shrink_rescale,steps_per_contact,friction,tangential_restitution,tangential_restitution_closed,spin_rad_s,spin_closed_rad_s,patch_restitution,rebound_angle_deg,energy_ratio",
          string.format("%g,%s,%d,%g,%g,%.10g,%s,%.10g,%s,%.10g,%.10g,%.10g", angle, model, p.shrink_rescale, n, mu, e_t,
                        closed_e_t and string.format("%.10g", closed_e_t) or "", res.spin,
                        closed_spin and string.format("%.10g", closed_spin) or "", patch, rebound_angle,
                        res.energy_ratio))
    end
  end
end

for name, f in pairs(csv_files) do f:close() end
if #missed > 0 then error("closed forms missed:\n  " .. table.concat(missed, "\n  "), 0) end
if p.check == 1 then print("\nchung_ooi ok") end
