-- sim:scale_velocities names one particle twice (it would be scaled twice)
-- expect: scale_velocities_listed_twice\.lua:10\b.*lists particle 1 twice
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:scale_velocities { factor = 2, particles = { 1, 2, 1 } }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
