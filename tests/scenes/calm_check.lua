-- granule.calm: the settling criterion compares the kinetic energy with the
-- free particles' mass moving at the rest speed, so the same fraction of a
-- scene's speed scale judges beads of any size alike.
local granule = require "granule"
local H = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/../analysis/helpers.lua")

-- One free sphere at speed u and one fixed sphere: E = m u^2 / 2 with the
-- free mass only; calm exactly when u < rest_speed.
local function scene(radius, u)
  local sim = simulation { dimension = 3 }
  sim:material { name = "glass", density = 2500 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0 }
  sim:add_particle { position = { 0, 0, 0 }, radius = radius, material = "glass", velocity = { u, 0, 0 } }
  sim:add_particle { position = { 0, 10 * radius, 0 }, radius = radius, material = "glass", fixed = true }
  return sim
end
for _, radius in ipairs { 1e-6, 1e-3, 0.05 } do
  local scale = math.sqrt(9.81 * 2 * radius)  -- the scenes' speed scale sqrt(g d)
  local u = 0.02 * scale
  local sim = scene(radius, u)
  H.check(granule.calm(sim, 0.021 * scale)(sim), "r = " .. radius .. ": moving below the rest speed is calm")
  H.check(not granule.calm(sim, 0.019 * scale)(sim), "r = " .. radius .. ": moving above it is not")
end

-- The mass is summed again when the particle count changes: a second free
-- sphere at rest halves the mean square speed.
local radius = 1e-3
local sim = scene(radius, 1.0)
local calm = granule.calm(sim, 0.8)
H.check(not calm(sim), "one sphere at 1 m/s is not calm at 0.8 m/s")
local extra = sim:add_particle { position = { 0, -10 * radius, 0 }, radius = radius, material = "glass" }
H.check(calm(sim), "the same energy over twice the free mass is an rms speed of 0.71 m/s: calm at 0.8 m/s")

-- One removed and one of twice the radius added: the mass is the one now there.
sim:remove_particle(extra)
sim:add_particle { position = { 0, -20 * radius, 0 }, radius = 2 * radius, material = "glass" }
H.check(calm(sim), "the same energy over nine times the free mass: calm at 0.8 m/s")
H.check(not granule.calm(sim, 0.3)(sim), "an rms speed of 1/3 m/s is not calm at 0.3 m/s")
-- No free particle: nothing moves.
local still = simulation { dimension = 3 }
still:material { name = "glass", density = 2500 }
still:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0 }
H.check(granule.calm(still, 1e-3)(still), "a scene without particles is calm")
still:add_particle { position = { 0, 0, 0 }, radius = radius, material = "glass", fixed = true }
H.check(granule.calm(still, 1e-3)(still), "a scene of fixed particles is calm")

-- A particle fixed or freed changes the free mass at once (sim:set_fixed): the
-- same energy over the one free sphere's mass alone is not calm.
local pair = scene(radius, 1.0)
local second = pair:add_particle { position = { 0, -10 * radius, 0 }, radius = radius, material = "glass" }
local judge = granule.calm(pair, 0.8)
H.check(judge(pair), "two free spheres, one moving at 1 m/s: an rms speed of 0.71 m/s, calm at 0.8 m/s")
pair:set_fixed(second, true)
H.check(pair:stats().free_mass == pair:particle(0).mass, "fixed: the free mass is the moving sphere's")
H.check(not judge(pair), "the resting sphere fixed: 1 m/s over the free mass, not calm")
pair:set_fixed(second, false)
H.check(judge(pair), "freed again: calm")

-- checks = 3: calm only at the third call in a row that finds it so; a call that
-- does not starts the count again (a ringing bed passing near rest once).
local ring = scene(radius, 1.0)
local thrice = granule.calm(ring, 0.8, 3)
H.check(not thrice(ring), "moving: not calm")
ring:set_velocity(0, { 0.5, 0, 0 })
H.check(not thrice(ring) and not thrice(ring), "below the rest speed at two calls: not yet")
ring:set_velocity(0, { 1.0, 0, 0 })
H.check(not thrice(ring), "moving again: the count starts over")
ring:set_velocity(0, { 0.5, 0, 0 })
H.check(not thrice(ring) and not thrice(ring), "two calls in the new run: not yet")
H.check(thrice(ring), "the third call in a row: calm")
H.fails("checks must be a whole number >= 1", granule.calm, ring, 0.8, 0)
H.fails("granule.calm: argument 3", granule.calm, ring, 0.8, 1.5)

H.fails("rest_speed must be > 0", granule.calm, sim, 0)
H.fails("rest_speed must be > 0", granule.calm, sim, -1)
H.fails("granule.calm: argument 2", granule.calm, sim, 0 / 0)
print("calm check ok")
