-- Stress: N -> 0 in the tangential laws. Grazing impacts (relative velocity at
-- 80-89.9 degrees to the line of centres, spinning spheres) load the tangential
-- spring while the normal force rises from and falls back to zero, and the
-- Walton-Braun contact ends in its permanent-set gap with N = 0. At every step
-- the tangential force must stay finite and within Coulomb's cap: |T| <= mu |N|
-- (Eqs. 3.5, 6.8-6.10), |T| <= mu (|N| + 2 Nc) for JKR (Eqs. 6.23-6.25).
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local mu, r, gamma = 0.4, 0.2e-3, 0.05
local laws = {
  linear = { model = "linear", k_normal = 2e4, restitution = 0.85, friction = mu },
  walton_braun = { model = "walton_braun", k_load = 2e4, restitution = 0.5, friction = mu },
  hertz_mindlin = { model = "hertz_mindlin", restitution = 0.85, friction = mu },
  thornton_elastic = { model = "thornton_elastic", friction = mu },
  thornton_jkr = { model = "thornton_jkr", friction = mu, surface_energy = gamma },
}
local checked = 0
for _, name in ipairs { "linear", "walton_braun", "hertz_mindlin", "thornton_elastic", "thornton_jkr" } do
  for _, angle in ipairs { 80, 89, 89.9 } do
    for _, spin in ipairs { 0, 2000 } do
      local sim = simulation { dimension = 3, record_contacts = true }
      sim:material { name = "m", density = 2500, young = 1e8, poisson = 0.3 }
      local law = { "m", "m" }
      for k, v in pairs(laws[name]) do law[k] = v end
      sim:contact(law)
      local speed = 0.5
      local c, s_ = math.cos(math.rad(angle)), math.sin(math.rad(angle))
      -- Offsets chosen so that the spheres meet: centres 1.9 r apart across the relative velocity.
      local b_off = 1.99 * r * math.sin(math.rad(angle))
      local a = sim:add_particle { position = { -4 * r, -b_off / 2, 0 }, velocity = { speed / 2, 0, 0 },
                                   spin = { 0, 0, spin }, radius = r, material = "m" }
      local b = sim:add_particle { position = { 4 * r, b_off / 2, 0 }, velocity = { -speed / 2, 0, 0 },
                                   spin = { 0, 0, -spin }, radius = r, material = "m" }
      local nc = name == "thornton_jkr" and 1.5 * math.pi * gamma * r / 2 or 0
      local steps_seen, worst = 0, 0
      sim:every { steps = 1, function(s)
        for _, k in ipairs(s:contacts()) do
          local t = math.sqrt(k.tangential_force[1] ^ 2 + k.tangential_force[2] ^ 2 + k.tangential_force[3] ^ 2)
          S.check(S.finite(t) and S.finite(k.normal_force), "%s at %s deg: non-finite force", name, angle)
          local cap = mu * (math.abs(k.normal_force) + 2 * nc)
          if name == "walton_braun" then cap = mu * math.max(k.normal_force, 0) end
          S.check(t <= cap * (1 + 1e-9) + 1e-15, "%s at %s deg, spin %s: |T| = %s N above the cap %s N (N = %s N)",
            name, angle, spin, t, cap, k.normal_force)
          if cap > 0 then worst = math.max(worst, t / cap) end
          steps_seen = steps_seen + 1
        end
      end }
      sim:run { duration = 16 * r / speed }
      S.all_finite(sim)
      S.check(steps_seen > 0 or angle > 89, "%s at %s deg: the spheres never touched", name, angle)
      checked = checked + steps_seen
    end
  end
end
S.check(checked > 1000, "only %s contact steps checked", checked)
print(string.format("stress.tangential_zero_normal: %d contact steps within the cap", checked))
print("stress.tangential_zero_normal ok")
