-- checkpoints into a folder that does not exist (found at the first signal otherwise)
-- expect: checkpoint_no_folder\.lua:11\b.*the folder no_such_folder does not exist
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:checkpoint { file = "no_such_folder/x.chk.h5", every_steps = 5 }  -- <- wrong
sim:run { steps = 10 }
