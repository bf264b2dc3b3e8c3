-- Stress: the Mechanofusion chamber of dissertation Table 4.1 (25 mm, inner
-- piece 10 mm leaving a 1.6 mm gap, 0.4 mm particles, Walton-Braun) turning at
-- 4000 rpm, twice the base case. Short in ctest (-L stress); 1e6 steps with the
-- full 1500 particles under -L stress_long. The chamber feeds energy in, so the
-- checks are bounds: every state finite, every particle inside the chamber and
-- outside the inner piece, no particle faster than 3x the chamber's surface
-- speed (a particle is dragged by the wall and squeezed in the gap, never shot).
-- The particles start at up to 2 m/s in random directions, so they reach the walls.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local granule = require "granule"
local p = parameters {
  steps = { default = 50000 },
  particles = { default = 300 },
  rpm = { default = 4000, unit = "1/min" },
  check_every = { default = 2000 },
}
local R, r_in, gap, r = 12.5e-3, 5e-3, 1.6e-3, 0.2e-3
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.4 }
sim:contact { "powder", "steel", model = "walton_braun", k_load = 2e4, restitution = 0.85, friction = 0.5 }
local omega = granule.rpm(p.rpm)
local offset = R - gap - r_in
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = R, inside = true, angular_velocity = omega,
                    material = "steel" }
sim:wall_cylinder { name = "inner_piece", center = { offset, 0 }, radius = r_in, inside = false, material = "steel" }
local ids = sim:fill { region = { circle = { center = { 0, 0 }, radius = R } }, count = p.particles, radius = r,
                       material = "powder", seed = 3, max_speed = 2, overlap = false }
S.check(#ids == p.particles, "placed %s of %s particles", #ids, p.particles)
local v_wall = omega * R
local vmax_seen, wall_hits = 0, 0
local function check(s)
  local f = s:wall("chamber").force
  if f[1] ~= 0 or f[2] ~= 0 then wall_hits = wall_hits + 1 end
  for _, id in ipairs(s:particles()) do
    local q = s:particle(id)
    local x, y = q.position[1], q.position[2]
    S.check(S.finite(x) and S.finite(y), "particle %s: non-finite position", id)
    local d = math.sqrt(x * x + y * y)
    S.check(d < R, "step %s: particle %s outside the chamber (%s m from its axis)", s:step_count(), id, d)
    local di = math.sqrt((x - offset) ^ 2 + y * y)
    S.check(di > r_in, "step %s: particle %s inside the inner piece", s:step_count(), id)
    local v = math.sqrt(q.velocity[1] ^ 2 + q.velocity[2] ^ 2)
    vmax_seen = math.max(vmax_seen, v)
    S.check(v < 3 * v_wall, "step %s: particle %s at %s m/s, above 3x the wall's %s m/s", s:step_count(), id, v,
      v_wall)
  end
end
sim:every { steps = p.check_every, check }
sim:every { steps = 50, function(q) local f = q:wall("chamber").force if f[1] ~= 0 or f[2] ~= 0 then wall_hits = wall_hits + 1 end end }
local t0 = wall_time()
sim:run { steps = p.steps }
check(sim)
local s = sim:stats()
S.check(wall_hits > 0, "no particle touched the chamber at any check")
-- The turning chamber drags the powder along: angular momentum about the axis in its sense.
S.check(s.angular_momentum_z > 0, "the powder does not turn with the chamber (L_z = %s)", s.angular_momentum_z)
print(string.format("stress.chamber_4000rpm: %d steps, %d particles, fastest %.3g m/s (wall %.3g m/s), "
  .. "%.3g s wall time", s.step, p.particles, vmax_seen, v_wall, wall_time() - t0))
print("stress.chamber_4000rpm ok")
