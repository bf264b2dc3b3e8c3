-- a second schedule of one target: it would overwrite the first at every step
-- expect: schedule_twice\.lua:12\b.*schedule 1 already sets it for 'glass'-'glass'
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:schedule { "friction", from = "glass", to = "glass", linear = { 0, 0.1, 1, 0.3 } }
sim:schedule { "friction", from = "glass", to = "glass", linear = { 0, 0.5, 1, 0.9 } }  -- <- wrong
sim:run { steps = 10 }
