-- The file's last snapshot is the scene's final state even when a callback
-- changed the particles on a step whose scheduled snapshot was already written
-- (here one removed at the last step of the run, where snapshot_every falls).
local sim = simulation { dimension = 2, time_step = 1e-5 }
sim:material { name = "m", density = 2500 }
sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 0.5 }
for k = 0, 2 do sim:add_particle { position = { 3e-3 * k, 0 }, radius = 1e-3, material = "m" } end
sim:output { snapshot_every = 0.01 }
sim:every { steps = 1000, function(s) s:remove_particle(2) end }
sim:run { steps = 1000 }
print("particles at the end: " .. #sim:particles())
