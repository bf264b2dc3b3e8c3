-- a schedule holding a switch at 0.5 (neither 0 nor 1; no ramp)
-- expect: schedule_switch_half\.lua:11\b.*'allow_tension' is a switch: its values are 0 or 1, not 0.5
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:schedule { "allow_tension", from = "glass", to = "glass", constant = 0.5 }  -- <- wrong
sim:run { steps = 10 }
