-- Is the cost linear in particles and contacts? The dense shaken 3D box of
-- tools/bench/box3d_compare.lua (spheres on a touching cubic lattice, four side
-- walls, a floor shaken at 50 Hz, linear contacts with friction) at several
-- sizes, each timed over `steps` steps after `warmup` steps, in one run:
-- particle-steps/s and the time per contact should stay flat as N grows.
-- (The lattice is still settling, so lists are rebuilt often: these runs are
-- slower per particle than the settled box of compare.py, at every size alike.)
--   build/granule run tools/bench/scaling.lua -q
--   build/granule run tools/bench/scaling.lua -D sides=10,20,30,40,50 -D layers=40 -q
local p = parameters {
  sides = { default = "12,18,25,35,50", doc = "spheres per side of the box, one run each" },
  layers = { default = 40 },
  radius = { default = 1e-3, unit = "m" },
  steps = { default = 300 },
  warmup = { default = 300 },
}
local r = p.radius
print("| spheres | pair contacts / sphere | list rebuilds / 100 steps | particle-steps/s | ns per step per sphere | ns per step per contact |")
print("|---|---|---|---|---|---|")
for side_text in string.gmatch(p.sides, "[^,]+") do
  local per_side = math.tointeger(tonumber(side_text))
  assert(per_side and per_side > 0, "sides: positive integers, got '" .. side_text .. "'")
  local spacing, side = 2 * r, per_side * 2 * r
  local sim = simulation { dimension = 3, time_step = 1.5e-6 }
  sim:material { name = "glass", density = 2500 }
  sim:material { name = "steel", density = 7800 }
  for _, other in ipairs { "glass", "steel" } do
    sim:contact { "glass", other, model = "linear", k_normal = 1e4, restitution = 0.5, friction = 0.5 }
  end
  sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
  sim:wall_plane { name = "x_low", point = { 0, 0, 0 }, normal = { 1, 0, 0 }, material = "steel" }
  sim:wall_plane { name = "x_high", point = { side, 0, 0 }, normal = { -1, 0, 0 }, material = "steel" }
  sim:wall_plane { name = "y_low", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "steel" }
  sim:wall_plane { name = "y_high", point = { 0, side, 0 }, normal = { 0, -1, 0 }, material = "steel" }
  sim:gravity { 0, 0, -9.81 }
  local omega = 2 * math.pi * 50
  sim:every { steps = 1, function(s)
    s:set_wall("floor", { velocity = { 0, 0, 0.1e-3 * omega * math.cos(omega * s:time()) } })
  end }
  local k = 0
  for layer = 0, p.layers - 1 do
    for iy = 0, per_side - 1 do
      for ix = 0, per_side - 1 do
        k = k + 1
        local jitter = 0.005 * r * math.sin(k * 12.9898)
        sim:add_particle { position = { (ix + 0.5) * spacing + jitter, (iy + 0.5) * spacing - jitter,
                                        (layer + 0.5) * spacing }, radius = r, material = "glass" }
      end
    end
  end
  sim:run { steps = p.warmup }
  local contacts, samples = 0, 0
  sim:every { steps = 50, function(s)
    contacts, samples = contacts + s:stats().contacts_particle, samples + 1
  end }
  local rebuilds0 = sim:stats().list_rebuilds
  local t0 = wall_time()
  sim:run { steps = p.steps }
  local wall = wall_time() - t0
  local n = sim:stats().particles
  local mean_contacts = contacts / math.max(samples, 1)
  local rebuilds = sim:stats().list_rebuilds - rebuilds0
  print(string.format("| %d | %.2f | %.1f | %.3g | %.1f | %.1f |", n, mean_contacts / n,
    100 * rebuilds / p.steps, n * p.steps / wall,
    1e9 * wall / (p.steps * n), 1e9 * wall / (p.steps * math.max(mean_contacts, 1))))
end
