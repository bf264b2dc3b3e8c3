-- two particles closing at 2000 m/s: in one step they overlap by more than a radius
-- expect: particles 0 and 1 pass through each other
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:add_particle { position = { -4e-4, 0 }, radius = 3e-4, material = "glass", velocity = { 1000, 0 } }
sim:add_particle { position = { 4e-4, 0 }, radius = 3e-4, material = "glass", velocity = { -1000, 0 } }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
