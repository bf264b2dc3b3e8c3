-- a fill of 5e8 particles, far more memory than the machine has
-- expect: fill_huge_count_memory\.lua:9\b.*particles need about .* GB
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5e8, radius = 1e-9, material = "glass" }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
