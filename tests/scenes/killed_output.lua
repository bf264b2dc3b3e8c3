-- Rows a run appended in its first steps, then none: killed (SIGKILL, no
-- handler runs) a few seconds into the run, the output must hold the rows and
-- the snapshot's walls (tests/scenes/killed_output_test.py).
local sim = simulation { dimension = 2 }
sim:material { name = "grain", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "grain", "grain", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:contact { "grain", "steel", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:gravity { 0, -9.81 }
sim:fill { region = { box = { lo = { 0, 0 }, hi = { 20e-3, 20e-3 } } }, count = 200, radius = 0.4e-3,
           material = "grain", seed = 1 }
sim:output { series_every = 0, snapshot_every = 0 }
sim:series("burst", { "time", "value" }, { "s", "m" })
-- Ten rows in the run's first 100 steps (well within its first second), then none.
local appended = 0
sim:every { steps = 10, function(s)
  if appended == 10 then return end
  appended = appended + 1
  s:append("burst", { s:time(), appended })
  if appended == 10 then
    print("appended")
    io.stdout:flush()
  end
end }
sim:run { duration = 1e3 }
