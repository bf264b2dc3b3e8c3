-- Preparation of a random-packing agglomerate (dissertation 7.3, Figs. 7.9-7.12):
-- 217 Al2O3 primaries of seven sizes over 5 um +- 5 %, generated at random in
-- a 100 um circle, pulled together by a centripetal field with zero friction
-- and zero surface energy, then friction and surface energy switched on, then
-- the field removed gradually. The first snapshot of the output is the random
-- start (Fig. 7.10), the last the agglomerate (Fig. 7.12) that the test scenes
-- load (agglomerate_*_impact.lua, agglomerate_compression.lua).
--
--   granule run scenarios/agglomerate_prepare.lua -D surface_energy=1 -o agglomerate_2d_g1.h5
--   granule run scenarios/agglomerate_prepare.lua -D dimension=3 -o agglomerate_3d_g1.h5
--   /usr/bin/python3 tools/plot_agglomerate.py agglomerate_2d_g1.h5
local agglomerate = require "granule.agglomerate"
local d = agglomerate.preparation_defaults

local p = parameters {
  dimension = { default = 2 },
  protocol = { default = d.protocol, doc = "dense (7.3 literally) or sticky (friction and adhesion on while compacting)" },
  compaction_friction = { default = -1, doc = "mu while the field compacts; -1: the protocol's" },
  compaction_surface_energy = { default = -1, unit = "J/m^2", doc = "Gamma while the field compacts; -1: the protocol's" },
  switch_order = { default = d.switch_order, doc = "together, friction_first or adhesion_first" },
  surface_energy_steps = { default = d.surface_energy_steps, doc = "Gamma raised in this many steps" },
  decrement_duration = { default = d.decrement_duration, unit = "s", doc = "per field decrement; 0: until rest" },
  count = { default = d.count, doc = "number of primaries" },
  surface_energy = { default = d.surface_energy, unit = "J/m^2" },
  friction = { default = d.friction },
  mean_diameter = { default = d.mean_diameter, unit = "m" },
  generation_diameter = { default = d.generation_diameter, unit = "m", doc = "0: 100 um (2D), 25 % solids (3D)" },
  seed = { default = d.seed },
  field_strength = { default = d.field_strength, unit = "m/s^2" },
  damping_rate = { default = d.damping_rate, unit = "1/s" },
  rest_speed = { default = d.rest_speed, unit = "m/s" },
  field_decrements = { default = d.field_decrements },
  quiet_duration = { default = d.quiet_duration, unit = "s" },
}

-- -1 (the default) is "the protocol's"; any other negative value is a mistake.
for _, name in ipairs { "compaction_friction", "compaction_surface_energy" } do
  if p[name] < 0 and p[name] ~= -1 then
    require("granule.checks").fail("agglomerate_prepare", name, ">= 0, or -1 for the protocol's", p[name])
  end
end
local sim = simulation { dimension = p.dimension, record_contacts = true }
local out = sim:output {}
local clock = os.clock()
local options = {
  protocol = p.protocol, switch_order = p.switch_order, surface_energy_steps = p.surface_energy_steps,
  decrement_duration = p.decrement_duration, count = p.count, surface_energy = p.surface_energy, friction = p.friction, mean_diameter = p.mean_diameter,
  generation_diameter = p.generation_diameter, seed = p.seed, field_strength = p.field_strength,
  damping_rate = p.damping_rate, rest_speed = p.rest_speed, field_decrements = p.field_decrements,
  quiet_duration = p.quiet_duration, snapshot_generated = true,
}
if p.compaction_friction >= 0 then options.compaction_friction = p.compaction_friction end
if p.compaction_surface_energy >= 0 then options.compaction_surface_energy = p.compaction_surface_energy end
local report = agglomerate.prepare(sim, options)
agglomerate.write_preparation(sim, report)
-- The last snapshot and, beside it, the contact histories of the same step, so
-- that a test starts from exactly the prepared state.
agglomerate.save(sim, out, report)
print(agglomerate.preparation_line(report) .. string.format(" cpu_time_s=%.3g", os.clock() - clock))
io.stderr:write("agglomerate written to " .. out .. " (last snapshot, contact histories)\n")
