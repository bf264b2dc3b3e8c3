-- A scene of three stages with Lua between them, for the restart tests
-- (tests/scenes/restart_stages_test.py): each stage's start is printed, so
-- that the test can interrupt the run inside it; what the script reads, the
-- values its callbacks accumulate, its results, series and snapshots must
-- all come out the same after a restart as in a run that never stopped.
local p = parameters {
  checkpoint = { default = "stages.chk.h5" },
  stage_steps = { default = 60000, doc = "steps in each stage" },
  checkpoint_every = { default = 5000 },
  busy = { default = 0, doc = "iterations of Lua arithmetic between stages one and two" },
  snapshot_every = { default = 2e-3, unit = "s" },
}
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.1 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 6e-3, angular_velocity = 150, material = "steel" }
-- A finite wall that moves (a slotted plate rising through the bed): its position
-- and velocity are state a restart must bring back.
sim:wall_disk { name = "plate", center = { 0, -4e-3 }, normal = { 0, 1 }, radius = 2e-3,
                inner_radius = 0.5e-3, velocity = { 0.01, 0.02 }, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 6e-3 } }, count = 400, radius = 0.2e-3,
           material = "powder", seed = 3, max_speed = 0.05, overlap = false }
sim:gravity { 0, -9.81 }
sim:output { snapshot_every = p.snapshot_every }
sim:checkpoint { file = p.checkpoint, every_steps = p.checkpoint_every }
sim:series("stage_log", { "time", "kinetic_energy", "peak" })
-- A diagnostic whose averaging windows (3.3e-4 s) straddle the checkpoints.
local drum_force = sim:diagnostic("wall_force", { wall = "drum", window = 3.3e-4, every = 3 })

local peak, fired = 0, 0
sim:every { steps = 500, function(s)
  fired = fired + 1
  local e = s:stats().kinetic_energy
  if e > peak then peak = e end
  s:append("stage_log", { s:time(), e, peak })
end }

local function mark(stage)
  print(string.format("stage %s t=%.17g step=%d ke=%.17g peak=%.17g fired=%d clock=%s", stage,
    sim:time(), sim:step_count(), sim:stats().kinetic_energy, peak, fired, tostring(os.clock() >= 0)))
  io.stdout:flush()
end

-- A friction ramp that stage two ends (sim:remove_schedule) before setting
-- friction by hand: a restart must replay the removal, or the set is refused
-- and the checkpoint's schedules differ from the scene's.
local ramp = sim:schedule { "friction", from = "powder", to = "powder", linear = { 0, 0.1, 1, 0.3 } }
mark("one")
local r1 = sim:run { steps = p.stage_steps }
print("run one", r1.steps, r1.time, r1.stopped)
sim:result { after_one = sim:stats().kinetic_energy }
-- Lua's own work between two runs (a signal there stops the script, not a run).
if p.busy > 0 then
  print("busy")
  io.stdout:flush()
  local sum = 0
  for i = 1, p.busy do sum = sum + math.sin(i) end
  print(string.format("busy sum %.6f", sum))
end
local x0 = sim:particle(0).position
sim:remove_schedule(ramp)
sim:set_contact("powder", "powder", { friction = 0.4 })
sim:set_velocity(0, { 0.02, 0.01 })
-- Damping on for stage two and turned off by a callback in stage three: a
-- restart must bring back the value in effect at its checkpoint.
sim:set_damping { viscous = 5, spin = 5, local_fraction = 0.1 }
mark("two")
local r2 = sim:run { steps = p.stage_steps, check_every = 700,
                     stop_when = function(s) return s:stats().kinetic_energy < 1e-15 end }
print("run two", r2.steps, r2.time, r2.stopped, x0[1], x0[2])
sim:set_wall("drum", { angular_velocity = -100 })
sim:set_wall("plate", { velocity = { -0.01, -0.02 } })
local t3_half = sim:time() + 0.5 * p.stage_steps * sim:time_step()
local late = 0
sim:every { steps = 300, function(s)
  late = late + s:particle(1).velocity[1]
  if s:damping().viscous > 0 and s:time() > t3_half then s:set_damping {} end
end }
-- A restitution ramp over stage three's first half: Walton-Braun's unloading
-- stiffens (K_unload = K_load / e^2), so the automatic step shrinks on the way
-- and the run takes more steps than it planned to reach its end time.
local t3, stage_time = sim:time(), p.stage_steps * sim:time_step()
sim:schedule { "restitution", from = "powder", to = "powder",
               linear = { t3, 0.85, t3 + 0.5 * stage_time, 0.5 } }
mark("three")
local r3 = sim:run { duration = stage_time }
mark("end")
assert(r3.time >= t3 + stage_time * (1 - 1e-12) and r3.steps > p.stage_steps,
       string.format("run three ended at t = %.17g s after %d steps, short of %.17g s",
                     r3.time, r3.steps, t3 + stage_time))
print("run three", r3.steps, r3.time, r3.stopped, string.format("late=%.17g", late))
local plate = sim:wall("plate")
print(string.format("plate at %.17g %.17g, force %.17g %.17g", plate.center[1], plate.center[2],
  plate.force[1], plate.force[2]))
sim:result { peak = peak, fired = fired, late = late }
local means = sim:diagnostic_results(drum_force)
local keys = {}
for k in pairs(means) do keys[#keys + 1] = k end
table.sort(keys)
for _, k in ipairs(keys) do print(string.format("wall_force %s = %.17g", k, means[k])) end
