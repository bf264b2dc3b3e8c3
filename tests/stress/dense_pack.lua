-- Stress: a dense pack compressed by a piston, then held for a long time. The
-- only energy source is the piston's work W = -integral F_wall . v_wall dt, so
-- E = kinetic + elastic (1/2 k_n a^2 + |T|^2 / (2 k_t) per linear contact) may
-- never exceed E(0) + W; once the piston stops, E may only fall.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters {
  compress_steps = { default = 50000 },
  hold_steps = { default = 20000 },
  count = { default = 120 },
  check_every = { default = 100 },
}
local k, ratio = 2e4, 2 / 7
local r = 0.2e-3
local sim = simulation { dimension = 2, record_contacts = true }
sim:material { name = "m", density = 1200 }
sim:material { name = "steel", density = 0 }
for _, other in ipairs { "m", "steel" } do
  -- No tangential dashpot: the tangential force is then the spring's, k_t times its elongation.
  sim:contact { "m", other, model = "linear", k_normal = k, restitution = 0.7, friction = 0.3,
                tangential_ratio = ratio, tangential_damping_ratio = 0 }
end
local half = 3e-3
sim:wall_plane { name = "left", point = { -half, 0 }, normal = { 1, 0 }, material = "steel" }
sim:wall_plane { name = "right", point = { half, 0 }, normal = { -1, 0 }, material = "steel" }
sim:wall_plane { name = "bottom", point = { 0, -half }, normal = { 0, 1 }, material = "steel" }
sim:wall_plane { name = "piston", point = { 0, half }, normal = { 0, -1 }, material = "steel" }
local ids = sim:fill { region = { box = { lo = { -half, -half }, hi = { half, half } } }, count = p.count,
                       radius = r, material = "m", seed = 7, max_speed = 0.05, overlap = false }
S.check(#ids == p.count, "placed %s of %s particles", #ids, p.count)
sim:run { steps = 1 }
local e0 = S.energy(sim, k, ratio * k)
local work, worst_excess, peak = 0, 0, e0
local speed = 0.8
sim:set_wall("piston", { velocity = { 0, -speed } })
local v_wall = -speed
sim:every { steps = 1, function(s)
  -- Work on the particles this step: the wall pushes with -F (F: by the particles on the wall).
  work = work - s:wall("piston").force[2] * v_wall * s:time_step()
end }
sim:every { steps = p.check_every, function(s)
  local e = S.energy(s, k, ratio * k)
  worst_excess = math.max(worst_excess, (e - (e0 + work)) / (e0 + work))
  peak = math.max(peak, e)
end }
sim:run { steps = p.compress_steps }
S.all_finite(sim)
S.check(sim:stats().contacts_particle > p.count, "the piston did not compress the pack (%s contacts)",
  sim:stats().contacts_particle)
S.check(worst_excess < 0.02, "energy exceeded E0 + piston work by %s", worst_excess)
-- Hold: no source; energy may only fall (within leap-frog's half-step offset of the kinetic energy).
sim:set_wall("piston", { velocity = { 0, 0 } })
v_wall = 0
local held = S.energy(sim, k, ratio * k)
local grew = 0
sim:every { steps = p.check_every, function(s)
  grew = math.max(grew, (S.energy(s, k, ratio * k) - held) / held)
end }
sim:run { steps = p.hold_steps }
S.all_finite(sim)
S.check(grew < 0.02, "with the piston held, energy grew by %s", grew)
print(string.format("stress.dense_pack: work %.4g J, excess over E0 + W %.3g, growth while held %.3g",
  work, worst_excess, grew))
print("stress.dense_pack ok")
