-- sim:add_particle: position = { 0, 0 }, radius = 3e-4, material = "glass", fixed = true, velocity = { 1, 0 }
-- expect: particle_fixed_moving\.lua:9\b.*fixed particle is immobile
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:add_particle { position = { 0, 0 }, radius = 3e-4, material = "glass", fixed = true, velocity = { 1, 0 } }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
