-- A Lua diagnostic on sim:arrays() in a checkpointed run (tests/scenes/views_restart_test.sh):
-- restarted from its last checkpoint, the run and its /profile series are bit-identical to
-- the uninterrupted one's.
local p = parameters { file = { default = "views_restart.chk.h5", doc = "checkpoint file" } }
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "walton_braun", k_load = 2e3, restitution = 0.85, friction = 0.4 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, inside = true, material = "glass" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.01 } }, count = 60, radius = 5e-4,
           material = "glass", seed = 3, overlap = false }
sim:gravity { 0, -9.81 }
sim:output { snapshot_every = 0.002 }
sim:checkpoint { file = p.file, every_steps = 700 }
local row, sum = {}, {}
sim:series("profile", { "time", "vx_low", "vx_high", "speed_sum" }, { "s", "m/s", "m/s", "m/s" })
sim:every { steps = 50, function(s)
  local P = s:arrays()
  local y, vx, vy = P.y, P.vx, P.vy
  sum[1], sum[2], sum[3], sum[4], sum[5] = 0, 0, 0, 0, 0
  for i = 1, #P do
    local k = y[i] < 0 and 1 or 2
    sum[k], sum[k + 2] = sum[k] + vx[i], sum[k + 2] + 1
    sum[5] = sum[5] + math.sqrt(vx[i] * vx[i] + vy[i] * vy[i])
  end
  row[1], row[2], row[3], row[4] = s:time(), sum[1] / math.max(sum[3], 1), sum[2] / math.max(sum[4], 1), sum[5]
  s:append("profile", row)
end }
sim:run { steps = 3000 }
print(string.format("views_restart: t = %.9g s", sim:time()))
