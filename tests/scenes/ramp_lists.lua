-- A schedule that ramps a contact law's friction changes the law every step;
-- the neighbour lists do not depend on it and must not be rebuilt every step
-- (a ramp over a settled pile once cost a rebuild, and its cell grid, a step).
-- The ramped run rebuilds no more often than the same run without the ramp,
-- and the ramp acts: the friction reached differs from the start's.
local function pile(ramp)
  local sim = simulation { dimension = 3 }
  sim:material { name = "glass", density = 2500, young = 1e7, poisson = 0.3 }
  sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
  sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "glass" }
  sim:fill { region = { box = { lo = { -4e-3, -4e-3, 0 }, hi = { 4e-3, 4e-3, 16e-3 } } }, count = 300,
             radius = 0.5e-3, material = "glass", seed = 2, overlap = false }
  sim:gravity { 0, 0, -9.81 }
  sim:run { steps = 2000 }
  if ramp then
    local t0, dt = sim:time(), sim:time_step()
    sim:schedule { "friction", from = "glass", to = "glass", linear = { t0, 0.3, t0 + 400 * dt, 0.7 } }
  end
  local before = sim:stats().list_rebuilds
  sim:run { steps = 500 }
  return sim, sim:stats().list_rebuilds - before
end

local plain, plain_rebuilds = pile(false)
local ramped, ramped_rebuilds = pile(true)
assert(ramped_rebuilds <= plain_rebuilds + 1,
  string.format("the friction ramp rebuilt the lists %d times in 500 steps (without it: %d)", ramped_rebuilds,
    plain_rebuilds))
local friction = ramped:contact_parameters("glass", "glass").friction
assert(math.abs(friction - 0.7) < 1e-12, "the ramp ended at friction " .. tostring(friction))
local moved = 0
for _, id in ipairs(plain:particles()) do
  local a, b = plain:particle(id).position, ramped:particle(id).position
  if a[1] ~= b[1] or a[2] ~= b[2] or a[3] ~= b[3] then moved = moved + 1 end
end
print(string.format("ramp lists ok: %d rebuilds with the ramp, %d without; %d of %d particles elsewhere",
  ramped_rebuilds, plain_rebuilds, moved, #plain:particles()))
