-- a wall at 1e4 m/s moves farther in one step than the smallest radius
-- expect: wall 'floor' moves .* more than the smallest free particle's radius
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.05 }
sim:material { name = "steel", density = 0, young = 2e8, poisson = 0.3, surface_energy = 0.05 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, velocity = { 0, 0, 1e4 }, material = "steel" }  -- <- wrong
sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
