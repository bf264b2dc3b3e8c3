-- A two-stage scene for the checkpoint/restart tests: settle in a rotating
-- drum, change the friction, then run until a criterion or a step budget,
-- checkpointing every `checkpoint_every` steps.
local p = parameters {
  checkpoint = { default = "restart_test.chk.h5" },
  checkpoint_every = { default = 2000 },
  stage2_steps = { default = 9000 },
}
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.1 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 6e-3, angular_velocity = 150, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 6e-3 } }, count = 400, radius = 0.2e-3,
           material = "powder", seed = 3, max_speed = 0.05, overlap = false }
sim:gravity { 0, -9.81 }
sim:output { snapshot_every = 1e-4 }
sim:checkpoint { file = p.checkpoint, every_steps = p.checkpoint_every }
local peak = 0
sim:every { steps = 500, function(s) peak = math.max(peak, s:stats().kinetic_energy) end }
sim:run { steps = 3000 }
sim:set_contact("powder", "powder", { friction = 0.4 })
local r = sim:run { steps = p.stage2_steps, check_every = 250,
                    stop_when = function(s) return s:stats().kinetic_energy < 1e-12 end }
local x = sim:particle(0).position
print(string.format("restart-scene step=%d stopped=%s x0=%.17g y0=%.17g", sim:step_count(),
  tostring(r.stopped), x[1], x[2]))
