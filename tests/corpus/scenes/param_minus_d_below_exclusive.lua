-- -D value of the wrong kind (-D count=0)
-- expect: -D count=0: 'count' must be > 0
-- args: -D count=0
local p = parameters { count = { default = 5, above = 0 } }
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = p.count, radius = 3e-4, material = "glass" }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
