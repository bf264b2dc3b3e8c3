-- a fill without overlaps asking for half the region's volume: random placement jams first
-- expect: fill_region_jammed\.lua:9\b.*placed only .* the region is too full for particles that may not overlap
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 1e8, poisson = 0.3, surface_energy = 0.05 }
sim:material { name = "steel", density = 0, young = 2e8, poisson = 0.3, surface_energy = 0.05 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.8, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
sim:fill { region = { box = { lo = { -0.002, -0.002, 0.001 }, hi = { 0.002, 0.002, 0.004 } } }, count = 212, radius = 3e-4, material = "glass", seed = 2, overlap = false }  -- <- wrong
sim:output {}
sim:run { steps = 10 }
