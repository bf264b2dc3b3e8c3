-- Stress: parallel bonds at the edge of stability. A cluster (2D and 3D), packed
-- by a central field, is bonded at every touching pair (4-6 bonds a particle)
-- with bonds as stiff as the time step allows: first a stiffness far too high,
-- which must be refused naming the stiffness and the limit; then 0.99 of the
-- limit it named. The bond's limit bounds the fastest mode of the whole
-- cluster (Gershgorin: each particle's bonds summed, src/engine/simulation_bonds.cpp),
-- so a dense cluster needs softer bonds than a pair (its collective mode is up to
-- sqrt(bonds a particle) times faster than one bond's). The cluster is
-- kicked and run 2e4 steps: every state finite, no bond broken (the strengths are
-- far above any load), and the kinetic energy never above its start (the bonds'
-- springs store what they take, the contacts only dissipate).
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local r, dt = 5e-4, 1e-6
local checked = 0
for _, d in ipairs { 2, 3 } do
  local function v(x, y, z) if d == 3 then return { x, y, z } end return { x, y } end
  local sim = simulation { dimension = d, time_step = dt }
  sim:material { name = "glass", density = 2500 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.9, friction = 0.3 }
  local region = d == 3 and { sphere = { center = v(0, 0, 0), radius = 6 * r } }
    or { circle = { center = { 0, 0 }, radius = 8 * r } }
  sim:fill { region = region, count = d == 3 and 60 or 25, radius = r, material = "glass", seed = 2, overlap = false }
  sim:central_field { point = v(0, 0, 0), strength = 50 }
  sim:run { duration = 0.05 }
  sim:central_field { point = v(0, 0, 0), strength = 0 }
  local strong = { tensile_strength = 1e12, shear_strength = 1e12, gap = 1e-5 }
  local function bond(k)
    return sim:bond { normal_stiffness = k, shear_stiffness = k, tensile_strength = strong.tensile_strength,
                      shear_strength = strong.shear_strength, gap = strong.gap }
  end
  local message = S.fails("normal_stiffness = 1e+14 Pa/m", bond, 1e14)
  S.check(message:find("is the stiffest", 1, true), "%dD: the refusal does not name the stiffest particle: %s", d, message)
  local limit = tonumber(message:match("1/omega = ([%d%.e%-]+) s"))
  S.check(limit and limit < dt, "%dD: no limit below the step in: %s", d, message)
  local k = 1e14 * (limit / dt) ^ 2 * 0.99 ^ 2
  local made = bond(k)
  local ids = sim:particles()
  S.check(made >= 1.5 * #ids, "%dD: only %s bonds for %s particles", d, made, #ids)
  for i, id in ipairs(ids) do sim:set_velocity(id, v(0.01 * math.sin(i), 0.01 * math.cos(i), 0.005)) end
  local ke0 = sim:stats().kinetic_energy
  sim:every { steps = 50, function(s)
    local ke = s:stats().kinetic_energy
    S.check(S.finite(ke) and ke <= ke0 * (1 + 1e-6), "%dD: kinetic energy %s J above its start %s J at step %s",
      d, ke, ke0, s:step_count())
    checked = checked + 1
  end }
  sim:run { steps = 20000 }
  S.all_finite(sim)
  S.check(sim:bond_counts().broken == 0, "%dD: %s bonds broke", d, sim:bond_counts().broken)
  print(string.format("stress.stiff_bonds: %dD, %d bonds on %d particles at 0.99 of the limit %.3g s: stable",
    d, made, #ids, limit))
end
S.check(checked > 500, "only %s samples", checked)
print("stress.stiff_bonds ok")
