-- Stress: a time step above the stable limit is refused with a message naming the
-- limit and the pair that sets it; one between the Eq. 4.1 rule and the limit is
-- warned and runs, its results bounded (never garbage); an automatic step follows
-- a stiffness changed between runs.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local k, e = 2e4, 0.85
local function pair(time_step)
  local sim = simulation { dimension = 2, time_step = time_step, record_contacts = true }
  sim:material { name = "m", density = 1200 }
  sim:contact { "m", "m", model = "linear", k_normal = k, restitution = e }
  local a = sim:add_particle { position = { -0.201e-3, 0 }, velocity = { 0.5, 0 }, radius = 0.2e-3, material = "m" }
  local b = sim:add_particle { position = { 0.201e-3, 0 }, velocity = { -0.5, 0 }, radius = 0.2e-3, material = "m" }
  return sim, a, b
end
local rule = pair(nil):time_step_rule()
-- Leap-frog on a spring: stable for omega dt < 2 (omega from the stiffest pair).
local m_star = S.sphere_mass(0.2e-3, 1200) / 2
-- Leap-frog's own limit is 2/omega, but near it an impact gains energy (restitution 1.1 at
-- 0.8 (2/omega), 3 at 0.99): the accepted limit is half of it, 1/omega.
S.relative(rule.stability_limit, 1 / math.sqrt(k / m_star), 1e-9, "accepted limit 1/omega")
S.check(rule.rule < rule.stability_limit, "the rule %s is not below the limit %s", rule.rule, rule.stability_limit)
for _, factor in ipairs { 1.0, 1.5, 100 } do
  local sim = pair(factor * rule.stability_limit)
  local message = S.fails("stability limit", sim.run, sim, { steps = 10 })
  S.check(message:find("time_step", 1, true) and message:find("m-m", 1, true),
    "the refusal names neither the parameter nor the pair: %s", message)
  S.check(sim:step_count() == 0, "a refused run advanced %s steps", sim:step_count())
end
-- Between the rule and the limit: runs (warned), and the impact stays physical:
-- the restitution stays below 1 (and above 0.7, for e = 0.85).
for _, fraction in ipairs { 0.05, 0.2, 0.5, 0.8, 0.99 } do
  local sim, a, b = pair(fraction * rule.stability_limit)
  local ended, seen = false, false
  sim:every { steps = 1, function(s)
    local n = #s:contacts()
    if n > 0 then seen = true elseif seen then ended = true end
  end }
  sim:run { steps = 10000, check_every = 1, stop_when = function() return ended end }
  S.check(ended, "dt = %s of the limit: contact never ended", fraction)
  S.all_finite(sim)
  local va, vb = sim:particle(a).velocity[1], sim:particle(b).velocity[1]
  local restitution = (vb - va) / 1.0
  S.check(restitution > 0.7 and restitution < 1, "dt = %s of the limit: restitution %s", fraction, restitution)
end
-- steps_per_contact: the automatic dt = t_c / n must meet the same limit. Leap-frog on
-- the linear law accepts n > pi / sqrt(1 - zeta^2) (t_c = pi / omega_d against 1/omega),
-- Walton-Braun n > pi (t_c e sqrt(m*/K1) pi against sqrt(m*/K2) = e sqrt(m*/K1)), Hertz
-- n > 16 (8 T_R / n against T_R / 2). Below: refused before any step, naming the parameter,
-- the dt, the limit and the pair; at and above: runs, its impact physical.
-- With friction the tangential spring's mode counts too: omega_t^2 = 3.5 k_t / m*
-- (the slip turns the particles, spheres in 2D as in 3D: 1/m + r^2/I = 3.5/m each),
-- so Walton-Braun's default tau = 0.8 (k_t = tau K2) needs n > pi sqrt(2.8) = 5.26,
-- and the linear law with k_t = k_n n > pi sqrt(3.5) / sqrt(1 - zeta^2) = 5.89 (its
-- default k_t = 2/7 k_n makes the two modes equal).
local laws = {
  linear = { model = "linear", k_normal = k, restitution = e },
  linear_stiff_tangential = { model = "linear", k_normal = k, restitution = e, friction = 0.5,
                              tangential_ratio = 1 },
  walton_braun = { model = "walton_braun", k_load = k, restitution = e },
  walton_braun_friction = { model = "walton_braun", k_load = k, restitution = e, friction = 0.5 },
  hertz_mindlin = { model = "hertz_mindlin", restitution = e },
}
local function impact(law, n)
  local sim = simulation { dimension = 2, steps_per_contact = n, record_contacts = true }
  sim:material { name = "m", density = 1200, young = 1e8, poisson = 0.3 }
  local c = { "m", "m" }
  for key, value in pairs(laws[law]) do c[key] = value end
  sim:contact(c)
  local a = sim:add_particle { position = { -0.201e-3, 0 }, velocity = { 0.5, 0 }, radius = 0.2e-3, material = "m" }
  local b = sim:add_particle { position = { 0.201e-3, 0 }, velocity = { -0.5, 0 }, radius = 0.2e-3, material = "m" }
  return sim, a, b
end
for law, cases in pairs { linear = { refused = { 1, 2, 3 }, runs = { 4, 10 } },
                          linear_stiff_tangential = { refused = { 3, 5.8 }, runs = { 5.95, 10 } },
                          walton_braun = { refused = { 1, 3 }, runs = { 4, 10 } },
                          walton_braun_friction = { refused = { 3, 5.2 }, runs = { 5.3, 10 } },
                          hertz_mindlin = { refused = { 1, 8, 16 }, runs = { 17, 40 } } } do
  for _, n in ipairs(cases.refused) do
    local sim = impact(law, n)
    local message = S.fails("stability limit", sim.run, sim, { steps = 10 })
    S.check(message:find("steps_per_contact = " .. n, 1, true) and message:find("m-m", 1, true)
      and message:find("time step", 1, true), "%s, n = %s: the refusal names neither n, dt nor the pair: %s",
      law, n, message)
    S.check(sim:step_count() == 0, "%s, n = %s: a refused run advanced %s steps", law, n, sim:step_count())
  end
  for _, n in ipairs(cases.runs) do
    local sim, a, b = impact(law, n)
    local seen, ended = false, false
    sim:every { steps = 1, function(s)
      if #s:contacts() > 0 then seen = true elseif seen then ended = true end
    end }
    sim:run { steps = 10000, check_every = 1, stop_when = function() return ended end }
    S.check(ended, "%s, n = %s: contact never ended", law, n)
    S.all_finite(sim)
    local restitution = sim:particle(b).velocity[1] - sim:particle(a).velocity[1]
    S.check(restitution > 0.5 and restitution < 1, "%s, n = %s: restitution %s", law, n, restitution)
  end
end
-- The automatic step follows the stiffness: 100x stiffer, 10x shorter (Eq. 4.1, t_c ~ k^-1/2).
local sim = pair(nil)
sim:run { steps = 1 }
local dt0 = sim:time_step()
sim:set_contact("m", "m", { k_normal = 100 * k })
sim:run { steps = 1 }
S.relative(sim:time_step(), dt0 / 10, 1e-6, "automatic time step after k_n x 100")
print("stress.dt_limit ok")
