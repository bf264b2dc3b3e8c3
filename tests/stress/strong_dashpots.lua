-- Stress: dashpots too strong for the step. An explicit dashpot c on a mass m stops the
-- relative motion in one step at c dt / m = 1 and reverses it beyond; past 2 the motion
-- grows step by step. The linear law near e = 0 (its rule t_c / n grows as
-- 1/sqrt(1 - zeta^2)) is refused where c_n dt / m* would pass 1, naming the limit, and
-- runs once n is large enough, its rebound below the approach. The EPSD rolling dashpot
-- (eta_r up to 100) is held at C_r dt (1/I_i + 1/I_j) = 1: a sphere resting on a floor or
-- on a fixed sphere, kicked to 1e-9 rad/s, does not spin up.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")

-- The linear law at e = 1e-14: refused at the default n, runs at n = 200.
local law = { model = "linear", k_normal = 1e3, restitution = 1e-14 }
S.fails("stability limit", S.head_on, { law = law, speed = 1, radius = 1e-3, density = 2500 })
for _, e in ipairs { 1e-3, 0.05 } do
  local out = S.head_on { law = { model = "linear", k_normal = 1e3, restitution = e }, speed = 1,
                          radius = 1e-3, density = 2500, steps_per_contact = 200 }
  S.check(out.restitution >= 0 and out.restitution <= e * 1.02,
    "linear, e = %s at n = 200: rebound %s", e, out.restitution)
end
do  -- e = 1e-14 at n = 200: the pair stops against each other and stays (no rebound to end it)
  local sim = simulation { dimension = 2, steps_per_contact = 200 }
  sim:material { name = "m", density = 2500 }
  sim:contact { "m", "m", model = "linear", k_normal = 1e3, restitution = 1e-14 }
  local a = sim:add_particle { position = { -1.001e-3, 0 }, velocity = { 0.5, 0 }, radius = 1e-3, material = "m" }
  local b = sim:add_particle { position = { 1.001e-3, 0 }, velocity = { -0.5, 0 }, radius = 1e-3, material = "m" }
  sim:run { steps = 4000 }
  local closing = sim:particle(a).velocity[1] - sim:particle(b).velocity[1]
  S.check(math.abs(closing) < 1e-3, "linear, e = 1e-14 at n = 200: relative speed %s after the impact", closing)
end

-- A resting sphere with a strong rolling dashpot, in 2D and 3D, on a plane and on a fixed
-- sphere: the kick dies away.
for _, dimension in ipairs { 2, 3 } do
  for _, target in ipairs { "plane", "particle" } do
    for _, eta in ipairs { 5, 100 } do
      local r, kn = 1e-3, 1e3
      local sim = simulation { dimension = dimension }
      sim:material { name = "ball", density = 2500 }
      sim:material { name = "floor", density = target == "particle" and 2500 or 0 }
      for _, other in ipairs { "ball", "floor" } do
        sim:contact { "ball", other, model = "linear", k_normal = kn, restitution = 0.5, friction = 2,
                      rolling_friction = 1, rolling_model = "epsd", rolling_damping = eta }
      end
      sim:contact { "floor", "floor", model = "linear", k_normal = kn, restitution = 0.5 }
      local function v(x, y) if dimension == 3 then return { x, y, 0 } end return { x, y } end
      local m = S.sphere_mass(r, 2500)
      local y0
      if target == "plane" then
        sim:wall_plane { name = "floor", point = v(0, 0), normal = v(0, 1), material = "floor" }
        y0 = r - m * 9.81 / kn
      else
        sim:add_particle { position = v(0, -r), radius = r, material = "floor", fixed = true }
        y0 = r + (r - 2 * m * 9.81 / kn)
      end
      sim:gravity(v(0, -9.81))
      local kick = 1e-9
      local id = sim:add_particle { position = v(0, y0), radius = r, material = "ball",
                                    spin = dimension == 3 and { 0, 0, kick } or kick }
      local late = 0
      sim:every { steps = 1, function(s)
        if s:time() > 0.05 then
          local w = s:particle(id).spin
          late = math.max(late, math.abs(dimension == 3 and w[3] or w))
        end
      end }
      sim:run { duration = 0.1 }
      S.all_finite(sim)
      S.check(late < kick, "%dD, %s, eta_r = %s: spin %s rad/s late in the run after a kick of %s",
        dimension, target, eta, late, kick)
    end
  end
end
print("stress.strong_dashpots ok")
