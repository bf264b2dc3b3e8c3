-- restitution 1e-300: K2 = K1 / e^2 overflows
-- expect: walton_braun_restitution_underflow\.lua:6\b.*restitution = 1e-300 makes the unloading stiffness K2 = K1 / e\^2 \(Eq. 3.1\) overflow
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "walton_braun", k_load = 1e4, restitution = 1e-300, friction = 0.3 }  -- <- wrong
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
