-- Output that documents itself (tests/io/output_units_test.py): units on every dataset,
-- every parameter and every series; gravity and the central field in /scene; snapshots
-- with force, torque and the contact network. Three spheres in 3D: a pair pressed
-- together on a floor and one alone in the air.
local p = parameters {
  radius = { default = 1e-3, unit = "m", doc = "sphere radius" },
  overlap = { default = 2e-5, unit = "m", doc = "initial overlap of each contact" },
  label = { default = "three spheres", doc = "a text parameter (no unit)" },
  file = { default = "output_documented_test.h5", doc = "output file" },
  seed = { default = 7, integer = true, doc = "a whole number: written as an integer" },
  speed = { default = 3, unit = "m/s", doc = "a whole default, not declared whole: written as a double" },
}
local r, d = p.radius, p.overlap
local sim = simulation { dimension = 3, time_step = 1e-6, record_contacts = true }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.9, friction = 0.3 }
sim:wall_plane { name = "floor", material = "glass", point = { 0, 0, 0 }, normal = { 0, 0, 1 } }
sim:gravity { 0, 0, -9.81 }
sim:central_field { point = { 0, 0, 1 }, strength = 0.5 }
sim:add_particle { position = { 0, 0, r - d }, velocity = { 0.01, 0, 0 }, radius = r, material = "glass" }
sim:add_particle { position = { 2 * r - d, 0, r - d }, radius = r, material = "glass" }
sim:add_particle { position = { 0, 0.01, 0.01 }, radius = r, material = "glass" }
sim:output { file = p.file, forces = true, contacts = true }
sim:diagnostic("wall_force", { wall = "floor", label = "floor" })
sim:diagnostic("overlaps", { every = 2, window = 5e-6 })  -- a group whose units are one per column
sim:series("probe", { "time", "height" }, { "s", "m" })
sim:series("plain", { "time", "whatever" })
sim:every { steps = 5, function(s)
  sim:append("probe", { s:time(), s:particle(2).position[3] })
  sim:append("plain", { s:time(), 1 })
end }
sim:run { steps = 10 }
-- A later stage's wall: its material and law reach the file with it.
sim:material { name = "rubber", density = 0 }
sim:contact { "glass", "rubber", model = "linear", k_normal = 2e3, restitution = 0.5 }
sim:wall_plane { name = "lid", material = "rubber", point = { 0, 0, 0.05 }, normal = { 0, 0, -1 } }
sim:snapshot()  -- with the output's forces and contacts
sim:run { steps = 10 }
sim:snapshot { forces = false, contacts = false }
sim:snapshot { forces = false, contacts = false }  -- the same state at the same step: not again
sim:close()
print("output_documented ok")
