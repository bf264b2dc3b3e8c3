-- Stress: a particle started overlapping a wall. Up to its radius it is warned
-- and pushed out with no more energy than the spring held, (1/2) k a0^2; a centre
-- beyond the wall is refused, naming the particle and the wall.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local k, r = 2e4, 0.2e-3
local function scene(overlap, model)
  local sim = simulation { dimension = 2 }
  sim:material { name = "m", density = 1200 }
  sim:material { name = "steel", density = 0 }
  sim:contact { "m", "steel", model = model, k_normal = model == "linear" and k or nil,
                k_load = model == "walton_braun" and k or nil, restitution = 0.85, friction = 0.5 }
  sim:contact { "m", "m", model = model, k_normal = model == "linear" and k or nil,
                k_load = model == "walton_braun" and k or nil, restitution = 0.85, friction = 0.5 }
  sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
  local id = sim:add_particle { position = { 0, r - overlap }, velocity = { 0.01, 0 }, radius = r, material = "m" }
  return sim, id
end
for _, model in ipairs { "linear", "walton_braun" } do
  for _, fraction in ipairs { 0.1, 0.5, 0.99 } do
    local a0 = fraction * r
    local sim, id = scene(a0, model)
    local e0 = sim:stats().kinetic_energy
    sim:run { steps = 3000 }
    S.all_finite(sim)
    local p = sim:particle(id)
    S.check(p.position[2] > r, "%s, started %s r into the floor: still overlapping (y = %s)", model, fraction,
      p.position[2])
    S.check(p.velocity[2] > 0, "%s: not moving away from the floor", model)
    local gained = sim:stats().kinetic_energy - e0
    S.check(gained <= 0.5 * k * a0 ^ 2 * (1 + 1e-6), "%s, %s r: gained %s J, the spring held %s J", model,
      fraction, gained, 0.5 * k * a0 ^ 2)
  end
  local sim = scene(1.2 * r, model)
  local message = S.fails("outside wall 'floor'", sim.run, sim, { steps = 1 })
  S.check(message:find("particle 0", 1, true), "the refusal does not name the particle: %s", message)
end
print("stress.wall_overlap ok")
