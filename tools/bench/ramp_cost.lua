-- What a schedule that ramps a contact law costs: 5000 Hertz-Mindlin spheres
-- falling onto a floor for `steps` steps, with (-D ramp=1) or without (0) a
-- friction ramp over those steps. Prints the CPU seconds of the run and the
-- kinetic energy at its end (the ramp changes no motion before contacts form).
--   build/granule run tools/bench/ramp_cost.lua -D ramp=1 --threads 1 -q
local p = parameters {
  ramp = { default = 1, doc = "1: friction ramped from 0.3 to 0.6 over the run; 0: held at 0.3" },
  steps = { default = 2000, doc = "steps timed" },
  n = { default = 5000, doc = "spheres" },
}
local sim = simulation { dimension = 3 }
sim:material { name = "g", density = 2500, young = 1e7, poisson = 0.3 }
sim:contact { "g", "g", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "g" }
sim:fill { region = { box = { lo = { -0.02, -0.02, 0.0 }, hi = { 0.02, 0.02, 0.06 } } }, count = p.n,
           radius = 0.5e-3, material = "g", seed = 1, overlap = false }
sim:gravity { 0, 0, -9.81 }
if p.ramp == 1 then
  sim:schedule { "friction", from = "g", to = "g", linear = { 0, 0.3, p.steps * sim:time_step(), 0.6 } }
end
local t0 = os.clock()
sim:run { steps = p.steps }
print(string.format("ramp=%d cpu=%.2f s kinetic_energy=%.6g J", p.ramp, os.clock() - t0,
  sim:stats().kinetic_energy))
