-- Stress: when a run does go wrong it stops at once, names the step, the
-- particle and the contact (or wall), and the output keeps the state it had.
--   * a particle thrown at a plane so fast that its soft contact cannot stop it
--     within its radius (overlap v/omega > 2r): it tunnels through, and the run
--     stops naming the particle and the wall;
--   * the same particle at a speed the contact can stop bounces back with no more
--     energy than it brought;
--   * two overlapping particles given 1e308 m/s (finite, so accepted) overflow
--     the dashpot force to infinity: the run stops naming the step, the particle
--     and its contact, and the output keeps their last finite state.
-- tests/stress/check_failure.py then reads the two output files.
local S = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/stress.lua")
local p = parameters { prefix = { default = "stress_failure", doc = "output files <prefix>_tunnel.h5, _nan.h5" } }
local k, r = 2e4, 0.2e-3
local m = S.sphere_mass(r, 1200)
local omega = math.sqrt(k / m)

local function plate(speed, file)
  local sim = simulation { dimension = 2 }
  sim:material { name = "m", density = 1200 }
  sim:material { name = "steel", density = 0 }
  sim:contact { "m", "steel", model = "linear", k_normal = k, restitution = 0.9 }
  sim:contact { "m", "m", model = "linear", k_normal = k, restitution = 0.9 }
  sim:wall_plane { name = "plate", point = { 0, 0 }, normal = { -1, 0 }, material = "steel" }
  local id = sim:add_particle { position = { -3 * r, 0 }, velocity = { speed, 0 }, radius = r, material = "m" }
  if file then sim:output { file = file } end
  return sim, id
end

-- Stopped within 0.1 r (v/omega = 0.1 r): bounces, e <= 1.
local slow = 0.1 * r * omega
local sim, id = plate(slow)
sim:run { duration = 10 * math.pi / omega }
S.all_finite(sim)
local back = -sim:particle(id).velocity[1]
S.check(back > 0 and back <= slow, "rebound %s m/s from %s m/s", back, slow)

-- v/omega = 10 r: the centre ends up more than a radius beyond the plate.
local fast = 10 * r * omega
sim = plate(fast, p.prefix .. "_tunnel.h5")
local message = S.fails("escaped through wall 'plate'", sim.run, sim, { duration = 20 * math.pi / omega })
S.check(message:find("particle 0", 1, true) and message:find("step ", 1, true),
  "the message names neither step nor particle: %s", message)
sim:close()

-- NaN: the dashpot force of two particles closing at 2e308 m/s overflows.
sim = simulation { dimension = 2 }
sim:material { name = "m", density = 1200 }
sim:contact { "m", "m", model = "linear", k_normal = k, restitution = 0.9 }
local a = sim:add_particle { position = { -0.9 * r, 0 }, velocity = { 1e308, 0 }, radius = r, material = "m" }
sim:add_particle { position = { 0.9 * r, 0 }, velocity = { -1e308, 0 }, radius = r, material = "m" }
sim:output { file = p.prefix .. "_nan.h5" }
message = S.fails("non-finite", sim.run, sim, { steps = 10 })
S.check(message:find("step 1 ", 1, true) and message:find("particle " .. a, 1, true)
  and message:find("its contact with particle", 1, true),
  "the message does not name the step, the particle and its contact: %s", message)
sim:close()
print("stress.failures ok")
