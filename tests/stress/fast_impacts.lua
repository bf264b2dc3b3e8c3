-- Stress: impacts at 10x the usual speed (1 m/s in dissertation 3.4; 10 m/s here,
-- and 30 m/s on a wall). The automatic time step depends on the stiffness only, so
-- each contact is still resolved; the rebound never carries more energy than the
-- approach and the overlap stays a fraction of the radius.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters { factor = { default = 10, doc = "speed / 1 m/s" } }
local e = 0.85
for _, target in ipairs { "sphere", "wall" } do
  local wall = target == "wall"
  for _, speed in ipairs { p.factor, 3 * p.factor } do
    -- Walton-Braun (Eq. 3.4): e = sqrt(K1/K2) at any speed.
    local wb = S.head_on { speed = speed, wall = wall,
                           law = { model = "walton_braun", k_load = 2e4, restitution = e, friction = 0.4 } }
    S.relative(wb.restitution, e, 0.01, string.format("Walton-Braun restitution at %g m/s on a %s", speed, target))
    -- Largest overlap: all kinetic energy of the approach into the loading spring, v sqrt(m*/K1).
    local m_star = wall and wb.mass or wb.mass / 2
    local bound = speed * math.sqrt(m_star / 2e4)
    S.check(wb.max_overlap <= bound * 1.01, "overlap %s above the loading bound %s", wb.max_overlap, bound)
    S.check(wb.max_overlap < 0.2e-3, "overlap %s m larger than the radius at %s m/s", wb.max_overlap, speed)
    -- Hertz-Mindlin with damping: 0 < e <= 1.
    local hm = S.head_on { speed = speed, wall = wall, young = 3e9, poisson = 0.35,
                           law = { model = "hertz_mindlin", restitution = e, friction = 0.4 } }
    S.check(hm.restitution > 0 and hm.restitution <= 1 + 1e-6, "Hertz-Mindlin restitution %s at %s m/s",
      hm.restitution, speed)
  end
end
print("stress.fast_impacts ok")
