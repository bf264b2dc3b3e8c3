-- A run that prints from a callback while its progress line is up (tests/app/progress_test.py):
-- a sphere in free flight, a line printed every `print_every` steps.
local p = parameters {
  steps = { default = 400000, unit = "-", doc = "steps to take" },
  print_every = { default = 40000, unit = "-", doc = "steps between the scene's prints" },
}
local sim = simulation { dimension = 2, time_step = 1e-6 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e2, restitution = 0.9, friction = 0.3 }
sim:add_particle { position = { 0, 0 }, velocity = { 1, 0 }, radius = 1e-3, material = "glass" }
sim:every { steps = p.print_every, function(s) print(string.format("SCENE-PRINT step %d", s:step_count())) end }
sim:run { steps = p.steps }
