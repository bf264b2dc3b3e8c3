-- Stress: adhesive (JKR, dissertation 6.3.3) contacts at the pull-off edge.
--   1. Two stuck spheres pulled apart at a set speed (displacement control):
--      the force passes the pull-off force -Nc = -1.5 pi Gamma R* (Eq. 6.17) and
--      the contact ends at alpha_f = -(3/4)(pi^2 Gamma^2 R*/E*^2)^(1/3) with
--      N = -5/9 Nc (Thornton and Ning 1998), never pulling harder than Nc.
--   2. A pair driven to make and break contact every few steps: each contact
--      starts afresh (snap-on at -8/9 Nc), the force never passes -Nc, the state
--      stays finite.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters { cycles = { default = 40 } }
local r, young, poisson, gamma, density = 50e-6, 1e8, 0.3, 0.5, 2500
local e_star = young / (2 * (1 - poisson ^ 2))
local r_star = r / 2
local nc = 1.5 * math.pi * gamma * r_star
local alpha_f = -0.75 * (math.pi ^ 2 * gamma ^ 2 * r_star / e_star ^ 2) ^ (1 / 3)
local a0 = (4.5 * math.pi * gamma * r_star ^ 2 / e_star) ^ (1 / 3)  -- contact radius at N = 0
local delta0 = a0 ^ 2 / r_star - math.sqrt(2 * math.pi * gamma * a0 / e_star)  -- Eq. 6.14: overlap at N = 0

local function pair(overlap, friction)
  local sim = simulation { dimension = 3, record_contacts = true }
  sim:material { name = "m", density = density, young = young, poisson = poisson, surface_energy = gamma }
  sim:contact { "m", "m", model = "thornton_jkr", friction = friction }
  local half = r - overlap / 2
  local a = sim:add_particle { position = { -half, 0, 0 }, radius = r, material = "m" }
  local b = sim:add_particle { position = { half, 0, 0 }, radius = r, material = "m" }
  return sim, a, b
end

-- 1. Pull-off. Start at the zero-load overlap, then separate at u per side.
local sim, a, b = pair(delta0, 0.3)
local steps_to_separate = 4000
local u = (delta0 - alpha_f) / (2 * steps_to_separate * sim:time_step_rule().rule)
local min_force, last_force, last_overlap, ended = math.huge, nil, nil, false
-- Displacement control: the positions are set every step (a set velocity would
-- be undone by the contact's own pull within a step).
sim:every { steps = 1, function(s)
  local half = r - (delta0 - 2 * u * s:time()) / 2
  s:set_position(a, { -half, 0, 0 })
  s:set_position(b, { half, 0, 0 })
  s:set_velocity(a, { -u, 0, 0 })
  s:set_velocity(b, { u, 0, 0 })
  local list = s:contacts()
  if #list == 0 then ended = true return end
  min_force = math.min(min_force, list[1].normal_force)
  last_force, last_overlap = list[1].normal_force, list[1].overlap
end }
sim:run { steps = 3 * steps_to_separate, check_every = 1, stop_when = function() return ended end }
S.check(ended, "the pulled contact never ended")
S.all_finite(sim)
S.relative(min_force, -nc, 2e-3, "largest pull, -Nc")
S.check(min_force >= -nc * (1 + 1e-9), "pulled harder than Nc: %s N", min_force)
S.relative(last_force, -5 / 9 * nc, 0.05, "force when the contact ends, -5/9 Nc")
S.relative(last_overlap, alpha_f, 0.02, "overlap when the contact ends, alpha_f")

-- 2. Make and break every few steps: the overlap swings between 2 alpha_f and 2 delta0 - 2 alpha_f
-- (past the separation point) with a period of 12 steps.
sim, a, b = pair(2 * alpha_f, 0.3)
local dt = sim:time_step_rule().rule
local period = 12 * dt
local amplitude = delta0 - 2 * alpha_f  -- half the swing of the overlap
local formed, was_touching, worst = 0, false, math.huge
sim:every { steps = 1, function(s)
  local t = s:time()
  local w = 2 * math.pi / period
  local overlap = 2 * alpha_f + amplitude * (1 - math.cos(w * t))
  local half = r - overlap / 2
  local pa = s:particle(a).position
  s:set_position(a, { -half, pa[2], 0 })   -- a keeps the sideways slip it is given below
  s:set_position(b, { half, 0, 0 })
  s:set_velocity(a, { 0, 0.01, 0 })   -- sideways slip exercises the tangential law too
  s:set_velocity(b, { 0, 0, 0 })
  local list = s:contacts()
  local touching = #list > 0
  if touching and not was_touching then formed = formed + 1 end
  was_touching = touching
  for _, c in ipairs(list) do
    worst = math.min(worst, c.normal_force)
    S.check(S.finite(c.normal_force) and S.finite(c.tangential_force[2]), "non-finite contact force")
  end
end }
sim:run { duration = p.cycles * period }
S.all_finite(sim)
S.check(formed >= p.cycles / 2, "the contact formed %s times in %s cycles", formed, p.cycles)
S.check(worst >= -nc * (1 + 1e-9), "a re-formed contact pulled %s N, beyond Nc = %s N", worst, nc)
print(string.format("stress.adhesive_edge: Nc = %.4g N, min force %.6g Nc, at separation %.4g Nc, "
  .. "alpha %.4g alpha_f; %d contacts formed in %d cycles", nc, min_force / nc, last_force / nc,
  last_overlap / alpha_f, formed, p.cycles))
print("stress.adhesive_edge ok")
