-- Diametrical compression of a prepared agglomerate between two walls
-- (dissertation 7.7, Figs. 7.31-7.36): the bottom wall is fixed, the top wall
-- moves down at the compression velocity until the strain (travel / height)
-- reaches 10 %, then stops; the run goes on until bond breakage has stopped and
-- the kinetic energy is steady. Walls as in 7.6 (E = 1000 GPa, nu = 0.45,
-- mu = 0.5). Damage and debris ratios are sampled into /breakage (with the
-- wall travel), the final fragments into /clusters.
--
--   granule run scenarios/agglomerate_prepare.lua -o agglomerate_2d_g1.h5
--   granule run scenarios/agglomerate_compression.lua -D file=agglomerate_2d_g1.h5 -D velocity=0.6 -o comp_0.6.h5
--   /usr/bin/python3 tools/plot_agglomerate.py comp_0.6.h5          # clusters, debris grey (Figs. 7.32-7.34)
--   /usr/bin/python3 tools/plot_breakage.py comp_0.6.h5 --x wall_travel
local tests = require "granule.agglomerate_tests"
local d = tests.defaults

local p = parameters {
  dimension = { default = 2, doc = "must match the agglomerate file" },
  file = { default = "agglomerate_2d_g1.h5", doc = "output of scenarios/agglomerate_prepare.lua" },
  velocity = { default = 0.6, unit = "m/s", doc = "speed of the top wall" },
  strain = { default = d.strain, doc = "wall travel / agglomerate height at which the wall stops" },
  surface_energy = { default = d.surface_energy, unit = "J/m^2",
                     doc = "between primaries; -1: the prepared file's (another is refused unless other_surface_energy)" },
  friction = { default = d.friction, doc = "between primaries; -1: the prepared file's" },
  other_surface_energy = { default = false, doc = "true: test at a surface_energy other than the prepared one" },
  wall_surface_energy = { default = d.wall_surface_energy, unit = "J/m^2" },
  sample_every = { default = d.sample_every, doc = "steps between breakage samples" },
  steady_time = { default = d.steady_time, unit = "s" },
  max_duration = { default = 600e-6, unit = "s" },
}

local sim = simulation { dimension = p.dimension, record_contacts = true }
local out = sim:output {}
local result = tests.run(sim, "compression", {
  file = p.file, velocity = p.velocity, strain = p.strain, surface_energy = p.surface_energy, friction = p.friction,
  other_surface_energy = p.other_surface_energy,
  wall_surface_energy = p.wall_surface_energy, sample_every = p.sample_every, steady_time = p.steady_time,
  max_duration = p.max_duration,
})
print(tests.summary_line(result))
io.stderr:write("results written to " .. out .. "\n")
