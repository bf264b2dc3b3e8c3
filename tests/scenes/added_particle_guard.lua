-- A column of four discs squeezed by a piston onto a floor, with a pair law far
-- too soft for the load: the discs pass through one another, and the run must
-- stop, naming the pair. With add = 1 a disc is added far from the column
-- between two runs, when the column's pairs are already deeper than
-- overlap_warning: the grace for the scene's own overlaps is the added disc's
-- and ends on the next step, so the column's pass-through still stops the run,
-- at the same step as without it (one process or several ranks).
local p = parameters { add = { default = 0, integer = true, min = 0, max = 1 } }
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1, restitution = 0.5, friction = 0 }
sim:contact { "glass", "steel", model = "linear", k_normal = 30, restitution = 0.5, friction = 0 }
local r = 1e-3
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:wall_plane { name = "piston", point = { 0, 8 * r }, normal = { 0, -1 }, material = "steel" }
for k = 0, 3 do sim:add_particle { position = { 0, r + 2 * r * k }, radius = r, material = "glass" } end
local v = 5e-3
sim:set_wall("piston", { velocity = { 0, -v } })
sim:run { duration = 0.8 * r / v }  -- the pairs pressed past overlap_warning
assert(sim:stats().max_overlap_ratio > 0.1, "the column is not yet pressed deep")
if p.add == 1 then sim:add_particle { position = { 0.05, 3e-3 }, radius = r, material = "glass" } end
sim:run { duration = 4.5 * r / v }
print("added_particle_guard: no stop")
