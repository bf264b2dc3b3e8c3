-- -D value of the wrong kind (-D count=1e300)
-- expect: -D count=1e300: 'count' must be a whole number >= 1 and <= 1000
-- args: -D count=1e300
local p = parameters { count = { default = 5, integer = true, min = 1, max = 1000 } }
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = p.count, radius = 3e-4, material = "glass" }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
