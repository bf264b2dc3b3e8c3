-- a wall named with a newline, which would split the checkpoint's lines
-- expect: wall_name_with_newline\.lua:9\b.*wall: name .* holds a '/' or a control character
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:wall_plane { name = "lid\nright", point = { 0, 0.009 }, normal = { 0, -1 }, material = "steel" }  -- <- wrong
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
sim:output {}
sim:run { steps = 10 }
