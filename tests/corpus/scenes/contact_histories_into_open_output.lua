-- contact histories saved into the run's own output, still open
-- expect: contact_histories_into_open_output\.lua:12\b.*still open by its run
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output { file = "open_output.h5" }
sim:run { steps = 10 }
sim:save_contact_histories { file = "open_output.h5", material = "glass" }  -- <- wrong
