-- Stress: rolling resistance at high spin. Spheres spinning at up to 3e4 rad/s
-- (a surface speed of 30 m/s for r = 1 mm) are set down on a floor, alone and
-- in a row touching each other, under each normal law and both rolling models
-- (contact/rolling.hpp). Sliding friction turns the spin into rolling, and the
-- rolling torque (EPSD type C, Ai et al. 2011; or the constant torque
-- mu_r R* N) then brings the spheres to rest. At every step: every state stays
-- finite; kinetic plus gravitational energy never rises above its start (the
-- contacts only take energy out; the springs' own share is bounded by a small
-- margin); and a lone sphere under the constant torque never spins backwards
-- once it rolls (the torque opposes the rolling, and is capped so that it
-- cannot reverse it within a step). At the stop the tangential spring, loaded
-- by the deceleration, unloads and rocks the sphere back by a small fraction of
-- the start's spin (a spring contact's own vibration, in any code with one); a
-- rolling torque that reversed the spin would drive it on, past the tolerance
-- of 1e-4 of the start's spin. tests/contact/test_rolling.cpp checks the torque
-- itself step by step. The run must end at rest.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local r, g, mu, mu_r = 1e-3, 9.81, 0.5, 0.3
local laws = {
  linear = { model = "linear", k_normal = 2e4, restitution = 0.5, friction = mu },
  hertz_mindlin = { model = "hertz_mindlin", restitution = 0.5, friction = mu },
  walton_braun = { model = "walton_braun", k_load = 2e4, restitution = 0.5, friction = mu },
}
local checked = 0
for _, dimension in ipairs { 2, 3 } do
  for _, name in ipairs { "linear", "hertz_mindlin", "walton_braun" } do
    for _, rolling_model in ipairs { "epsd", "constant" } do
      for _, spin in ipairs { 300, 3e4 } do
        for _, row in ipairs { 1, 4 } do
          local sim = simulation { dimension = dimension }
          sim:material { name = "m", density = 2500, young = 1e8, poisson = 0.3 }
          sim:material { name = "floor", density = 0, young = 1e8, poisson = 0.3 }
          for _, other in ipairs { "m", "floor" } do
            local law = { "m", other, rolling_friction = mu_r, rolling_model = rolling_model,
                          rolling_damping = rolling_model == "epsd" and 0.3 or nil }
            for k, v in pairs(laws[name]) do law[k] = v end
            sim:contact(law)
          end
          local origin = dimension == 2 and { 0, 0 } or { 0, 0, 0 }
          local up = dimension == 2 and { 0, 1 } or { 0, 1, 0 }
          sim:wall_plane { name = "floor", point = origin, normal = up, material = "floor" }
          sim:gravity(dimension == 2 and { 0, -g } or { 0, -g, 0 })
          local ids = {}
          for k = 1, row do
            local x = (k - 1) * 2 * r
            local w = (k % 2 == 1 and 1 or -1) * spin  -- neighbours counter-spinning: the hardest case
            ids[k] = sim:add_particle {
              position = dimension == 2 and { x, r } or { x, r, 0 }, radius = r, material = "m",
              spin = dimension == 2 and w or { 0, 0, w } }
          end
          local function energy()
            local e = sim:stats().kinetic_energy
            for _, id in ipairs(ids) do
              local p = sim:particle(id)
              e = e + p.mass * g * p.position[2]
            end
            return e
          end
          local e0 = energy()
          local m = sim:particle(ids[1]).mass
          local margin = 0.02 * row * m * g * r  -- the springs' stored share at rest, and round-off
          local rolled_sign = nil
          local function spin_z(id)
            local w = sim:particle(id).spin
            return type(w) == "table" and w[3] or w
          end
          local label = string.format("%dD %s %s spin %g row %d", dimension, name, rolling_model, spin, row)
          sim:every { steps = 20, function(s)
            local e = energy()
            S.check(S.finite(e), "%s: non-finite energy", label)
            S.check(e <= e0 + margin, "%s: energy rose from %s J to %s J at t = %s s", label, e0, e, s:time())
            if row == 1 and rolling_model == "constant" then
              local p = s:particle(ids[1])
              local w, v = spin_z(ids[1]), p.velocity[1]
              -- rolling without slip: v = -w r; once it rolls, the spin keeps its sign
              if rolled_sign == nil and math.abs(v + w * r) < 1e-3 * math.abs(spin) * r and math.abs(w) > 0 then
                rolled_sign = w > 0 and 1 or -1
              end
              if rolled_sign then
                S.check(w * rolled_sign >= -1e-4 * spin, "%s: spin reversed to %s rad/s at t = %s s", label, w, s:time())
              end
            end
            checked = checked + 1
          end }
          -- the slip phase lasts 2/7 w r / (mu g); rolling then stops within 0.7 v^2/(mu_r g)
          local v_roll = 2 / 7 * spin * r
          local t_end = math.min(2 / 7 * spin * r / (mu * g) + 1.5 * v_roll / (mu_r * g) + 0.05, 2.0)
          if spin > 1e4 then t_end = 0.05 end  -- the 3e4 rad/s cases: the violent start only
          sim:run { duration = t_end }
          local vmax = S.all_finite(sim)
          if spin < 1e4 and rolling_model == "constant" then
            S.check(vmax < 1e-3, "%s: still moving at %s m/s after %s s", label, vmax, t_end)
          end
        end
      end
    end
  end
end
S.check(checked > 1000, "only %s samples checked", checked)
print(string.format("stress.rolling_spin: %d samples finite, energy never rose", checked))
print("stress.rolling_spin ok")
