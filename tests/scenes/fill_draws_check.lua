-- sim:fill's draws: the radii follow the size rule whatever the crowding (each
-- drawn once, its places tried until one is free); two fills of one scene do not
-- repeat each other's draws; max_speed changes no place or radius; a fill that
-- fails adds nothing.
local function scene()
  local sim = simulation { dimension = 3 }
  sim:material { name = "g", density = 2500 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.9, friction = 0.3 }
  return sim
end
local box = { box = { lo = { 0, 0, 0 }, hi = { 0.01, 0.01, 0.01 } } }

-- 1000 radii uniform in [0.2, 0.6] mm that may not overlap, 19 % of the box: the
-- large ones find room less often, but their share must not fall.
local sim = scene()
local ids = sim:fill { region = box, count = 1000, radius_min = 2e-4, radius_max = 6e-4, material = "g", overlap = false }
local sum, large = 0, 0
for _, id in ipairs(ids) do
  local r = sim:particle(id).radius
  sum = sum + r
  if r > 5e-4 then large = large + 1 end
end
local mean = sum / #ids
-- The mean's standard error is 0.4 mm / sqrt(12 * 1000) = 3.7e-6 m.
assert(math.abs(mean - 4e-4) < 4 * 3.7e-6, string.format("mean radius %.4g m, not 4e-4", mean))
assert(math.abs(large / #ids - 0.25) < 4 * math.sqrt(0.25 * 0.75 / #ids), "share above 0.5 mm " .. large / #ids)

-- Two fills, no seeds given, into one region: no particle on another's centre.
sim = scene()
local a = sim:fill { region = box, count = 50, radius = 3e-4, material = "g" }
local b = sim:fill { region = box, count = 50, radius = 3e-4, material = "g" }
local same = 0
for _, i in ipairs(a) do
  local x = sim:particle(i).position
  for _, j in ipairs(b) do
    local y = sim:particle(j).position
    if math.abs(x[1] - y[1]) + math.abs(x[2] - y[2]) + math.abs(x[3] - y[3]) < 1e-12 then same = same + 1 end
  end
end
assert(same == 0, same .. " particles of the second fill on the first's centres")

-- max_speed draws from its own stream: the places and radii stay.
local function bed(speed)
  local s = scene()
  local got = s:fill { region = box, count = 200, radius_min = 2e-4, radius_max = 6e-4, material = "g",
                       overlap = false, max_speed = speed }
  return s, got
end
local s0, i0 = bed(0)
local s1, i1 = bed(1e-9)
for k = 1, #i0 do
  local p, q = s0:particle(i0[k]), s1:particle(i1[k])
  assert(p.radius == q.radius and p.position[1] == q.position[1] and p.position[3] == q.position[3],
    "particle " .. k .. " moved when only max_speed changed")
end
assert(s1:particle(i1[1]).velocity[1] ~= 0, "max_speed gave velocities")

-- A fill that cannot be placed (half the box, not overlapping: past jamming) adds nothing.
sim = scene()
sim:fill { region = box, count = 10, radius = 3e-4, material = "g" }
local ok, message = pcall(sim.fill, sim, { region = box, count = 4000, radius = 3e-4, material = "g", overlap = false })
assert(not ok and message:find("placed only", 1, true), tostring(message))
assert(#sim:particles() == 10, #sim:particles() .. " particles after the failed fill")
print("fill draws check ok")
