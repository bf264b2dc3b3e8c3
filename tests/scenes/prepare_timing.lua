-- A callback that changes what the time step depends on (here the stiffness,
-- every 37 steps: the stiffer law shortens the step) takes effect at the very
-- next step, whatever the chunks
-- sim:run advances in: a run stopped for checks every 5 steps (and so in
-- chunks of at most 5) ends in the same bits as a plain run, whose chunks
-- grow with the wall clock.
local function scene()
  local sim = simulation { dimension = 2 }
  sim:material { name = "glass", density = 2500 }
  sim:material { name = "steel", density = 7800 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.7, friction = 0.3 }
  sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.7, friction = 0.5 }
  sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel", angular_velocity = 20 }
  sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.009 } }, count = 150, radius = 3e-4,
             material = "glass", seed = 4, overlap = false, max_speed = 0.05 }
  sim:gravity { 0, -9.81 }
  local calls = 0
  sim:every { steps = 37, function(s)
    calls = calls + 1
    s:set_contact("glass", "glass", { k_normal = calls % 2 == 0 and 1e4 or 3e4 })
  end }
  return sim
end

local plain, checked = scene(), scene()
plain:run { steps = 3000 }
local checks = 0
checked:run { steps = 3000, check_every = 5, stop_when = function() checks = checks + 1 return false end }
assert(checks >= 600, "the checked run was not advanced in chunks of 5 steps")
assert(plain:time() == checked:time(), string.format("the runs ended at %a and %a s", plain:time(), checked:time()))
local differ = 0
for _, id in ipairs(plain:particles()) do
  local a, b = plain:particle(id), checked:particle(id)
  for k = 1, 2 do
    if a.position[k] ~= b.position[k] or a.velocity[k] ~= b.velocity[k] then differ = differ + 1 end
  end
end
assert(differ == 0, differ .. " coordinates differ between the plain and the checked run")
print("prepare timing ok: " .. #plain:particles() .. " particles, t = " .. plain:time())
