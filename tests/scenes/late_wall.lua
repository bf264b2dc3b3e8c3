-- A wall added after the run began is written to /walls at the next snapshot,
-- where it stands then, whatever the wall clock: here the scene stalls 1.2 s of
-- wall time just after adding a moving platen, long enough for the output's
-- once-a-second flush to fall between its snapshots.
local sim = simulation { dimension = 2, time_step = 1e-5 }
sim:material { name = "m", density = 2500 }
sim:material { name = "w" }
sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:contact { "m", "w", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "m" }
sim:output { snapshot_every = 1e-3 }  -- every 100 steps
sim:run { steps = 50 }
sim:wall_plane { name = "top", point = { 0, 0.01 }, normal = { 0, -1 }, material = "w",
                 velocity = { 0, -0.1 } }
sim:every { steps = 1, function(s)
  if s:step_count() == 52 then
    local started = os.clock()
    while os.clock() - started < 1.2 do end
  end
end }
sim:run { steps = 50 }
print(string.format("top at the snapshot: %.17g", sim:wall("top").point[2]))
