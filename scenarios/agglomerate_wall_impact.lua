-- Normal impact of a prepared agglomerate on a stationary wall (dissertation
-- 7.6, Figs. 7.24-7.30): wall rho = 6000 kg/m^3, E = 1000 GPa, nu = 0.45,
-- mu = 0.5; every primary given the impact velocity toward the wall. Runs until
-- the impact is over, bond breakage has stopped and the kinetic energy is
-- steady; the damage and debris ratios are sampled into /breakage, the final
-- fragments into /clusters.
--
--   granule run scenarios/agglomerate_prepare.lua -o agglomerate_2d_g1.h5
--   granule run scenarios/agglomerate_wall_impact.lua -D file=agglomerate_2d_g1.h5 -D velocity=0.5 -o wall_0.5.h5
--   /usr/bin/python3 tools/plot_agglomerate.py wall_0.5.h5          # clusters, debris grey (Figs. 7.25-7.28)
--   /usr/bin/python3 tools/plot_breakage.py wall_0.5.h5             # damage and debris vs time
--   granule run scenarios/agglomerate_wall_impact.lua -D file=agglomerate_2d_g1.h5 -D velocity=0.5 \
--     -D bonded=true -o wall_bonded_0.5.h5     # parallel bonds instead of adhesion (docs/agglomerates.md)
local tests = require "granule.agglomerate_tests"
local d = tests.defaults

local p = parameters {
  dimension = { default = 2, doc = "must match the agglomerate file" },
  file = { default = "agglomerate_2d_g1.h5", doc = "output of scenarios/agglomerate_prepare.lua" },
  velocity = { default = 0.5, unit = "m/s" },
  surface_energy = { default = d.surface_energy, unit = "J/m^2",
                     doc = "between primaries; -1: the prepared file's (another is refused unless other_surface_energy)" },
  friction = { default = d.friction, doc = "between primaries; -1: the prepared file's" },
  other_surface_energy = { default = false, doc = "true: test at a surface_energy other than the prepared one" },
  wall_surface_energy = { default = d.wall_surface_energy, unit = "J/m^2" },
  wall_friction = { default = d.wall_friction },
  sample_every = { default = d.sample_every, doc = "steps between breakage samples" },
  steady_time = { default = d.steady_time, unit = "s" },
  max_duration = { default = d.max_duration, unit = "s" },
  bonded = { default = false, doc = "parallel bonds hold the primaries, their law without adhesion" },
  bond_normal_stiffness = { default = 0, unit = "Pa/m", doc = "0: from the JKR contact at equilibrium" },
  bond_shear_stiffness = { default = 0, unit = "Pa/m", doc = "0: Mindlin's ratio to the normal one" },
  bond_tensile_strength = { default = 0, unit = "Pa", doc = "0: bond force = JKR pull-off of surface_energy" },
  bond_shear_strength = { default = 0, unit = "Pa", doc = "0: the tensile strength" },
  bond_radius_multiplier = { default = 1, doc = "bond radius / smaller primary radius" },
  time_step = { default = 0, unit = "s", doc = "0: automatic; stiffer bonds may need a smaller one" },
}

if p.time_step < 0 then
  require("granule.checks").fail("agglomerate_wall_impact", "time_step", ">= 0 s (0: automatic)", p.time_step)
end
local sim = simulation { dimension = p.dimension, record_contacts = true,
                         time_step = p.time_step > 0 and p.time_step or nil }
local out = sim:output {}
local result = tests.run(sim, "wall", {
  file = p.file, velocity = p.velocity, surface_energy = p.surface_energy, friction = p.friction,
  other_surface_energy = p.other_surface_energy,
  wall_surface_energy = p.wall_surface_energy, wall_friction = p.wall_friction, sample_every = p.sample_every,
  steady_time = p.steady_time, max_duration = p.max_duration,
  bonds = p.bonded and { normal_stiffness = p.bond_normal_stiffness, shear_stiffness = p.bond_shear_stiffness,
                         tensile_strength = p.bond_tensile_strength, shear_strength = p.bond_shear_strength,
                         radius_multiplier = p.bond_radius_multiplier } or false,
})
print(tests.summary_line(result))
io.stderr:write("results written to " .. out .. "\n")
