-- A script that reads a particle many times: its restart journal grows with
-- every read, and passing each size mark (GRANULE_JOURNAL_WARN_BYTES, then each
-- doubling) is warned of once; a restart warns only of the marks passed after
-- its checkpoint (tests/scenes/journal_warning_test.py).
local p = parameters { checkpoint = { default = "journal_warning.chk.h5" } }
local sim = simulation { dimension = 2, time_step = 1e-6 }
sim:material { name = "g", density = 2500 }
sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5 }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "g" }
local sum = 0
for _ = 1, 2000 do sum = sum + sim:particle(0).radius end
sim:save_checkpoint(p.checkpoint)
print("checkpoint saved")
io.stdout:flush()
for _ = 1, 2000 do sum = sum + sim:particle(0).radius end
print(string.format("read %d times", math.floor(sum / 1e-3 + 0.5)))
