-- Normal impact of a prepared agglomerate with a host particle (dissertation
-- 7.5, Figs. 7.11-7.23): host PMMA, d = 400 um, rho = 1190 kg/m^3,
-- E = 3.3 GPa, nu = 0.5, mu = 0.3; host and agglomerate move toward each other,
-- each at the impact velocity. Runs until the impact is over, bond breakage
-- has stopped and the agglomerate's kinetic energy is steady; the damage and
-- debris ratios are sampled into /breakage, the final fragments into /clusters.
--
--   granule run scenarios/agglomerate_prepare.lua -o agglomerate_2d_g1.h5
--   granule run scenarios/agglomerate_host_impact.lua -D file=agglomerate_2d_g1.h5 -D velocity=0.4 -o host_0.4.h5
--   /usr/bin/python3 tools/plot_agglomerate.py host_0.4.h5          # clusters, debris grey (Figs. 7.14-7.20)
--   /usr/bin/python3 tools/plot_breakage.py host_0.4.h5             # damage and debris vs time (Figs. 7.15-7.23)
local tests = require "granule.agglomerate_tests"
local d = tests.defaults

local p = parameters {
  dimension = { default = 2, doc = "must match the agglomerate file" },
  file = { default = "agglomerate_2d_g1.h5", doc = "output of scenarios/agglomerate_prepare.lua" },
  velocity = { default = 0.4, unit = "m/s", doc = "speed of each body" },
  surface_energy = { default = d.surface_energy, unit = "J/m^2",
                     doc = "between primaries; -1: the prepared file's (another is refused unless other_surface_energy)" },
  friction = { default = d.friction, doc = "between primaries; -1: the prepared file's" },
  other_surface_energy = { default = false, doc = "true: test at a surface_energy other than the prepared one" },
  host_diameter = { default = d.host_diameter, unit = "m" },
  gap = { default = d.gap, unit = "m", doc = "initial distance between host and agglomerate" },
  host_surface_energy = { default = d.host_surface_energy, unit = "J/m^2" },
  sample_every = { default = d.sample_every, doc = "steps between breakage samples" },
  steady_time = { default = d.steady_time, unit = "s" },
  max_duration = { default = d.max_duration, unit = "s" },
}

local sim = simulation { dimension = p.dimension, record_contacts = true }
local out = sim:output {}
local result = tests.run(sim, "host", {
  file = p.file, velocity = p.velocity, surface_energy = p.surface_energy, friction = p.friction,
  other_surface_energy = p.other_surface_energy, host_diameter = p.host_diameter, gap = p.gap,
  host_surface_energy = p.host_surface_energy, sample_every = p.sample_every, steady_time = p.steady_time,
  max_duration = p.max_duration,
})
print(tests.summary_line(result))
io.stderr:write("results written to " .. out .. "\n")
