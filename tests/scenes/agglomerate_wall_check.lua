-- Wall impacts (dissertation 7.6) of the small agglomerate written by
-- agglomerate_prepare_check.lua: a very slow impact breaks nothing, a 1 m/s
-- impact yields debris, and a larger surface energy yields less debris at the
-- same velocity (7.5.2). Each test writes its own file; every assertion can fail.
local tests = require "granule.agglomerate_tests"

local function wall_impact(velocity, surface_energy, name)
  local sim = simulation { dimension = 2, record_contacts = true }
  sim:output { file = name }
  -- Gamma = 2 on the agglomerate prepared at 1: asked for explicitly (it starts
  -- its test out of equilibrium, its contacts pulled tighter).
  local r = tests.run(sim, "wall", { file = "agglomerate_test.h5", velocity = velocity,
                                     surface_energy = surface_energy, other_surface_energy = true,
                                     quiet = true })
  print(tests.summary_line(r))
  assert(r.ended_by == "criterion", name .. ": ended by its cap")
  assert(r.contact_start >= 0 and r.impact_duration > 0, name .. ": the agglomerate never reached the wall")
  sim:close()
  return r
end

local slow = wall_impact(0.005, 1.0, "agglomerate_wall_slow.h5")
assert(slow.broken_bonds == 0 and slow.debris_ratio == 0 and slow.fragments == 1,
  string.format("a 5 mm/s impact broke %d bonds, debris ratio %g", slow.broken_bonds, slow.debris_ratio))

local weak = wall_impact(1.0, 1.0, "agglomerate_wall_gamma1.h5")
assert(weak.debris_ratio > 0.02, "a 1 m/s impact made no debris: debris ratio " .. weak.debris_ratio)
assert(weak.damage_ratio > 0.2, "a 1 m/s impact broke few bonds: damage ratio " .. weak.damage_ratio)
assert(weak.peak_damage_ratio >= weak.damage_ratio and weak.peak_damage_ratio < 1.5 * weak.damage_ratio,
  string.format("peak damage ratio %g against the final %g", weak.peak_damage_ratio, weak.damage_ratio))

local strong = wall_impact(1.0, 2.0, "agglomerate_wall_gamma2.h5")
assert(strong.debris_ratio < weak.debris_ratio,
  string.format("Gamma = 2 J/m^2 gave no less debris (%g) than Gamma = 1 (%g)", strong.debris_ratio, weak.debris_ratio))
assert(strong.damage_ratio < weak.damage_ratio,
  string.format("Gamma = 2 J/m^2 broke no fewer bonds (%g) than Gamma = 1 (%g)", strong.damage_ratio, weak.damage_ratio))
-- Another surface energy than the prepared one is refused unless asked for, and
-- left out (-1) the test takes the file's.
do
  local sim = simulation { dimension = 2, record_contacts = true }
  local ok, message = pcall(tests.run, sim, "wall", { file = "agglomerate_test.h5", velocity = 0.005,
                                                      surface_energy = 0.2, quiet = true })
  assert(not ok and message:find("prepared with 1 J/m^2", 1, true), "Gamma 0.2 on an agglomerate of 1: " ..
    tostring(message))
  sim:close()
end
-- A compression whose platens would come closer than a primary's diameter is refused.
do
  local sim = simulation { dimension = 2, record_contacts = true }
  local ok, message = pcall(tests.run, sim, "compression", { file = "agglomerate_test.h5", velocity = 1,
                                                             strain = 0.95, quiet = true })
  assert(not ok and message:find("closer than the largest primary's diameter", 1, true),
    "strain 0.95: " .. tostring(message))
  sim:close()
end
local prepared = wall_impact(0.005, -1, "agglomerate_wall_prepared.h5")
assert(prepared.surface_energy == 1.0, "left out, surface_energy is the file's 1 J/m^2: " .. prepared.surface_energy)
print("agglomerate_wall_check ok")
