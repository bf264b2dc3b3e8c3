-- twisting_friction in a 2D scene, whose spins (about z) never twist a contact
-- expect: twisting_in_2d\.lua:6\b.*twisting_friction = 0.1 acts about the contact normal.*3D only
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3, twisting_friction = 0.1 }  -- <- wrong
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
