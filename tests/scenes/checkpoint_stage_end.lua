-- A periodic checkpoint due at a run's last step is written before the next
-- run's first step: stages exactly every_steps long are saved (they used to be
-- saved never).
-- And a schedule may drive a central field declared with strength 0.
local p = parameters { checkpoint = { default = "checkpoint_stage_end.chk.h5" } }
os.remove(p.checkpoint)
local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1200 }
sim:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0.3 }
sim:add_particle { position = { 0, 0 }, radius = 0.2e-3, material = "m" }
sim:add_particle { position = { 1e-3, 0 }, radius = 0.2e-3, material = "m" }
sim:central_field { point = { 0.5e-3, 0 }, strength = 0 }
sim:schedule { "central_strength", linear = { 0, 0, 1e-3, 10 } }
sim:checkpoint { file = p.checkpoint, every_steps = 200 }
sim:run { steps = 200 }
sim:run { steps = 200 }
local f = io.open(p.checkpoint, "rb")
assert(f, "no checkpoint in two runs of exactly every_steps steps")
f:close()
os.remove(p.checkpoint)
sim:run { steps = 200 }
f = io.open(p.checkpoint, "rb")
assert(f, "no checkpoint at the third run's start (step 400)")
f:close()
assert(sim:describe():find("central field: on", 1, true), "the scheduled field is not on:\n" .. sim:describe())
print("checkpoint_stage_end ok")
