-- Stress: an 80:1 size ratio in one scene (a 4 mm disc among 0.05 mm ones, in a
-- closed box, no field). The automatic time step follows the small particles
-- (Eq. 4.1), the large one scans only the cells it reaches, and with no energy
-- source the kinetic energy never exceeds what the particles started with (the
-- springs hold the rest, never less than zero).
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters { steps = { default = 100000 }, count = { default = 400 } }
local big, small = 4e-3, 0.05e-3
local sim = simulation { dimension = 2 }
sim:material { name = "m", density = 2500 }
sim:material { name = "steel", density = 0 }
for _, other in ipairs { "m", "steel" } do
  sim:contact { "m", other, model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.4 }
end
local half = 5e-3
for name, w in pairs { left = { -half, 0, 1, 0 }, right = { half, 0, -1, 0 }, bottom = { 0, -half, 0, 1 },
                       top = { 0, half, 0, -1 } } do
  sim:wall_plane { name = name, point = { w[1], w[2] }, normal = { w[3], w[4] }, material = "steel" }
end
local giant = sim:add_particle { position = { 0, 0 }, radius = big, material = "m", velocity = { 0.05, 0 } }
local ids = sim:fill { region = { box = { lo = { -half, -half }, hi = { half, half } } }, count = p.count,
                       radius = small, material = "m", seed = 5, max_speed = 1, overlap = false }
S.check(#ids == p.count, "placed %s of %s small particles", #ids, p.count)
local e0 = sim:stats().kinetic_energy
local worst, touched_giant = 0, false
sim:every { steps = 100, function(s)
  local e = s:stats().kinetic_energy
  worst = math.max(worst, e / e0)
  local f = s:particle(giant).force
  if f[1] ~= 0 or f[2] ~= 0 then touched_giant = true end
end }
sim:run { steps = p.steps }
S.all_finite(sim)
local stats = sim:stats()
S.check(worst <= 1 + 1e-3, "kinetic energy grew to %s times its start with no source", worst)
S.check(touched_giant, "no small particle reached the large one")
-- Neighbour lists stay proportional to the particle count (the large disc alone
-- would put every small one in its 3x3 cells if cells followed its size).
S.check(stats.candidate_pairs < 20 * (p.count + 1), "%s candidate pairs for %s particles", stats.candidate_pairs,
  p.count + 1)
local rule = sim:time_step_rule()
S.check(rule.governing_pair:find("m-m", 1, true), "time step governed by %s", rule.governing_pair)
print("stress.size_ratio ok")
