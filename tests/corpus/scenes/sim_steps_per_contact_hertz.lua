-- steps_per_contact = 10 with Hertz's laws, whose rule is Thornton's 8 T_R / n
-- expect: steps_per_contact = 10 gives a time step .* \(8 T_R / n \(Eqs\. 6\.1-6\.2\) for glass-glass .* above the stability limit
local sim = simulation { dimension = 3, steps_per_contact = 10 }  -- <- wrong
sim:material { name = "glass", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.05 }
sim:material { name = "steel", density = 0, young = 2e8, poisson = 0.3, surface_energy = 0.05 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
