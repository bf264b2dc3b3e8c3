-- A valid scene for the corrupt-checkpoint cases (tests/corpus/make_checkpoints.py):
-- 40 overlapping discs under gravity in a drum, so that the checkpoint it writes at
-- step 20 holds particle-particle and particle-wall contacts with their histories.
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "walton_braun", k_load = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.004, material = "steel", angular_velocity = 5 }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.004 } }, count = 40, radius = 4e-4, material = "glass", seed = 3 }
sim:gravity { 0, -9.81 }
sim:output {}
sim:every { steps = 5, name = "probe", function(s) end }
sim:checkpoint { file = "valid.chk.h5", every_steps = 20 }
sim:run { steps = 40 }
