-- Stress: particles started with coincident centres. The contact normal is then
-- undefined; the engine picks one (a unit vector, never 0/0), the particles fly
-- apart, and they carry off no more energy than the springs held at the start:
-- (1/2) k (2r)^2 per pair for a linear spring (and for Walton-Braun, whose first
-- loading is K1, at most (1/2) K1 (2r)^2, Eqs. 3.1-3.2).
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local k, r = 2e4, 0.2e-3
for _, model in ipairs { "linear", "walton_braun" } do
  for _, dimension in ipairs { 2, 3 } do
    for _, count in ipairs { 2, 3 } do
      local sim = simulation { dimension = dimension }
      sim:material { name = "m", density = 1200 }
      sim:contact { "m", "m", model = model, k_normal = model == "linear" and k or nil,
                    k_load = model == "walton_braun" and k or nil, restitution = 0.85, friction = 0.4 }
      local origin = dimension == 3 and { 1e-3, 2e-3, 0 } or { 1e-3, 2e-3 }
      for _ = 1, count do sim:add_particle { position = origin, radius = r, material = "m" } end
      sim:run { steps = 2000 }
      local vmax = S.all_finite(sim)
      local stored = count * (count - 1) / 2 * 0.5 * k * (2 * r) ^ 2
      local kinetic = sim:stats().kinetic_energy
      S.check(kinetic > 0, "%s %dD x%d: the particles did not separate", model, dimension, count)
      S.check(kinetic <= stored * (1 + 1e-6), "%s %dD x%d: kinetic energy %s J above the stored %s J", model,
        dimension, count, kinetic, stored)
      S.check(sim:stats().contacts_particle == 0, "%s %dD x%d: still in contact after 2000 steps", model,
        dimension, count)
      local p = sim:stats().momentum
      S.check(math.abs(p[1]) + math.abs(p[2]) < 1e-12 * vmax * S.sphere_mass(r, 1200) * count + 1e-20,
        "%s: momentum not conserved (%s)", model, p[1])
    end
  end
end
print("stress.coincident ok")
