-- End-to-end check of 3D features through the Lua API: a periodic axis, a
-- moving plane wall, gravity, and a central field whose strength a callback
-- changes. Every assertion can fail.
local granule = require "granule"
local sim = simulation { dimension = 3, periodic = { axis = "z", origin = 0, length = 4e-3 } }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, -5e-3, 0 }, normal = { 0, 1, 0 }, material = "steel" }
-- side walls: without them spheres would roll on the infinite floor for ever
sim:wall_plane { name = "left", point = { -2e-3, 0, 0 }, normal = { 1, 0, 0 }, material = "steel" }
sim:wall_plane { name = "right", point = { 2e-3, 0, 0 }, normal = { -1, 0, 0 }, material = "steel" }
local ids = sim:fill { region = { box = { lo = { -2e-3, -4e-3, 0 }, hi = { 2e-3, 2e-3, 4e-3 } } },
                       count = 30, radius = 0.3e-3, material = "glass", seed = 3, max_speed = 0.05,
                       overlap = false }  -- no overlaps: no particle is shot off and still in flight
assert(#ids == 30)
sim:gravity { 0, -9.81, 0 }
sim:run { duration = 0.05 }
for _, id in ipairs(sim:particles()) do
  local x = sim:particle(id).position
  assert(x[3] >= 0 and x[3] < 4e-3, "periodic wrap failed: z = " .. x[3])
  assert(x[2] > -5e-3, "a particle went through the floor")
end
-- The walls carry the weight once things settle: the floor most of it, the
-- side walls by friction what the pile leans on them (as in a silo).
sim:run { duration = 0.5 }
local weight = 0
for _, id in ipairs(sim:particles()) do weight = weight + sim:particle(id).mass * 9.81 end
local floor = sim:wall("floor")
local held = -(floor.force[2] + sim:wall("left").force[2] + sim:wall("right").force[2])
assert(math.abs(held - weight) < 0.01 * weight,
  string.format("walls hold %.4g N vs weight %.4g N", held, weight))
-- Lift the floor with a set velocity: the pile moves up with it.
sim:set_wall("floor", { velocity = { 0, 0.01, 0 } })
local t0 = sim:time()
sim:run { duration = 0.05 }
local lifted = sim:wall("floor").point[2] + 5e-3
assert(math.abs(lifted - 0.01 * (sim:time() - t0)) < 1e-12, "floor moved " .. lifted)
-- A central field whose strength a callback ramps pulls the particles together.
sim:gravity { 0, 0, 0 }
sim:set_wall("floor", { velocity = { 0, 0, 0 } })
sim:central_field { point = { 0, 0, 2e-3 }, strength = 0 }
sim:every { steps = 100, function(s) s:set_central_strength(math.min(5, s:central_strength() + 0.5)) end }
sim:run { duration = 0.05 }
assert(sim:central_strength() == 5, "callback did not ramp the field: " .. sim:central_strength())
print("features_3d ok")
