-- A projectile under gravity whose time step changes between runs. Leap-frog
-- holds the velocity half a step behind the position; on the first step after
-- a change the kick spans half the old step and half the new, so the velocity
-- comes out half the new step behind and the height stays the closed form's to
-- round-off: z = (v0 - g dt1 / 2) t - g t^2 / 2, the given v0 being the velocity
-- at -dt1 / 2.
local g, v0, dt1 = 10, 1, 1e-5
local sim = simulation { dimension = 3, time_step = dt1 }
sim:material { name = "m", density = 1000 }
sim:gravity { 0, 0, -g }
local id = sim:add_particle { position = { 0, 0, 0 }, velocity = { 0, 0, v0 }, radius = 1e-3, material = "m" }
sim:run { steps = 1000 }
sim:set { time_step = 2.5e-6 }
sim:run { steps = 4000 }
sim:set { time_step = 4e-5 }
sim:run { steps = 250 }
local t, dt = sim:time(), sim:time_step()
assert(math.abs(t - 0.03) < 1e-15, "time " .. t)
local p = sim:particle(id)
local z = (v0 - g * dt1 / 2) * t - g * t * t / 2
assert(math.abs(p.position[3] - z) < 1e-13, string.format("height %.17g against %.17g", p.position[3], z))
local v = v0 - g * dt1 / 2 - g * (t - dt / 2)
assert(math.abs(p.velocity[3] - v) < 1e-12, string.format("velocity %.17g against %.17g", p.velocity[3], v))
print("time step change check ok")
