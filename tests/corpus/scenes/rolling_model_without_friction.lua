-- rolling_model given with neither rolling_friction nor twisting_friction (it would do nothing)
-- expect: rolling_model_without_friction\.lua:6\b.*act only with rolling_friction > 0 or twisting_friction > 0
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.05 }
sim:material { name = "steel", density = 0, young = 2e8, poisson = 0.3, surface_energy = 0.05 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3, rolling_model = "constant" }  -- <- wrong
sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
