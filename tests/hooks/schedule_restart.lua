-- A drum whose ramps are schedules (sim:schedule), for the restart test
-- (tests/scenes/restart_stages_test.py): the wall's spin rises linearly, the
-- powder's friction steps up through points, the central field decays; a run
-- interrupted in the middle of the ramps and restarted from its checkpoint
-- must print and write what the run that never stopped does, bit for bit.
local p = parameters {
  steps = { default = 60000, doc = "steps in the run" },
  checkpoint_every = { default = 5000 },
}
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.1 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 6e-3, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 6e-3 } }, count = 400, radius = 0.2e-3,
           material = "powder", seed = 5, max_speed = 0.05 }
sim:gravity { 0, -9.81 }
sim:central_field { point = { 0, 0 }, strength = 20 }
sim:output { snapshot_every = 2e-3 }
sim:checkpoint { file = "schedules.chk.h5", every_steps = p.checkpoint_every }
local duration = p.steps * sim:time_step()
sim:schedule { "wall_angular_velocity", wall = "drum", linear = { 0.1 * duration, 0, 0.8 * duration, 150 } }
sim:schedule { "friction", from = "powder", to = "powder",
               points = { { 0, 0.1 }, { 0.3 * duration, 0.1 }, { 0.3 * duration, 0.3 }, { 0.9 * duration, 0.5 } } }
sim:schedule { "central_strength", piecewise = { 0.2 * duration, 20, 0.6 * duration, 0 } }
sim:series("ramp", { "time", "kinetic_energy" })
sim:every { steps = 1000, function(s) s:append("ramp", { s:time(), s:stats().kinetic_energy }) end }
print(string.format("schedules start t=%.17g", sim:time()))
io.stdout:flush()
local r = sim:run { steps = p.steps }
local st = sim:stats()
print(string.format("schedules end t=%.17g steps=%d ke=%.17g omega=%.17g field=%.17g", sim:time(), r.steps,
  st.kinetic_energy, sim:wall("drum").angular_velocity, sim:central_strength()))
