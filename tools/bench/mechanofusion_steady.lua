-- Steady-state speed of the 2D Mechanofusion base case (Table 4.1, Walton-Braun):
-- settle for `settle` seconds, then time `measure` seconds and print particle-steps/s
-- with the per-stage breakdown.   build/granule run tools/bench/mechanofusion_steady.lua --quiet
local p = parameters { settle = { default = 0.05, unit = "s" }, measure = { default = 0.01, unit = "s" } }
local granule = require "granule"
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.4 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 12.5e-3, angular_velocity = granule.rpm(2000), material = "steel" }
sim:wall_cylinder { name = "inner", center = { 5.9e-3, 0 }, radius = 5e-3, inside = false, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 12.5e-3 } }, count = 1500, radius = 0.2e-3, material = "powder", seed = 1, max_speed = 0.01 }
sim:run { duration = p.settle }
local t0 = os.clock(); local tm0 = sim:timings()
local r = sim:run { duration = p.measure }
local wall = os.clock() - t0; local tm = sim:timings()
local s = sim:stats()
print(string.format("steps %d wall %.2f s  -> %.3g particle-steps/s  contacts pp %d pw %d", r.steps, wall, 1500 * r.steps / wall, s.contacts_particle, s.contacts_wall))
print(string.format("neighbor %.2f force %.2f integrate %.2f hooks %.2f", tm.neighbor - tm0.neighbor, tm.force - tm0.force, tm.integrate - tm0.integrate, tm.hooks - tm0.hooks))
