-- sim:bond without normal_stiffness, its shear_stiffness given: the missing key is named, not the present one
-- expect: bond_normal_stiffness_missing\.lua:10\b.*bond: 'normal_stiffness' is required
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:bond { shear_stiffness = 1e9, tensile_strength = 1e6, shear_strength = 1e6 }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
