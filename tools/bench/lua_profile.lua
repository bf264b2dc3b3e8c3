-- What a diagnostic written in Lua costs at array speed (sim:arrays, src/lua/wrap_views.cpp):
-- `per_side`^2 x `layers` spheres of r = 1 mm (10^5 by default) on a touching cubic lattice
-- settle under gravity in a box; every `every` steps a Lua callback bins the particles'
-- x-velocity by height (the velocity profile of docs/tutorial.md) into /profile. Prints
-- the run's wall time, the time spent in the callback and its share of the run.
--   build/granule run tools/bench/lua_profile.lua -q                 # with the diagnostic
--   build/granule run tools/bench/lua_profile.lua -q -D profile=false  # without, to compare
local p = parameters {
  per_side = { default = 50, unit = "-", doc = "spheres along x and y" },
  layers = { default = 40, unit = "-", doc = "layers of spheres along z" },
  steps = { default = 2000, unit = "-", doc = "steps to time" },
  every = { default = 100, unit = "-", doc = "steps between two profiles" },
  bins = { default = 20, unit = "-", doc = "height bins of the profile" },
  profile = { default = true, doc = "run the Lua diagnostic (false: the bare run)" },
  file = { default = "lua_profile.h5", doc = "output file" },
}
local r = 1e-3
local side, height = 2 * r * p.per_side, 2 * r * p.layers
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }
sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
sim:wall_plane { name = "floor", material = "glass", point = { 0, 0, 0 }, normal = { 0, 0, 1 } }
sim:wall_plane { name = "x0", material = "glass", point = { 0, 0, 0 }, normal = { 1, 0, 0 } }
sim:wall_plane { name = "x1", material = "glass", point = { side, 0, 0 }, normal = { -1, 0, 0 } }
sim:wall_plane { name = "y0", material = "glass", point = { 0, 0, 0 }, normal = { 0, 1, 0 } }
sim:wall_plane { name = "y1", material = "glass", point = { 0, side, 0 }, normal = { 0, -1, 0 } }
sim:gravity { 0, 0, -9.81 }
for k = 0, p.layers - 1 do
  for j = 0, p.per_side - 1 do
    for i = 0, p.per_side - 1 do
      sim:add_particle { position = { (2 * i + 1) * r, (2 * j + 1) * r, (2 * k + 1) * r },
                         velocity = { 0.01 * math.sin(i + 3 * j + 7 * k), 0, 0 }, radius = r,
                         material = "glass" }
    end
  end
end
sim:output { file = p.file, xdmf = false }

local spent = 0
if p.profile then
  local columns, units, row, sum, count = { "time" }, { "s" }, {}, {}, {}
  for b = 1, p.bins do columns[b + 1], units[b + 1] = "vx_" .. b, "m/s" end
  sim:series("profile", columns, units)
  local bins = p.bins
  sim:every { steps = p.every, function(s)
    local t0 = wall_time()
    local P = s:arrays()
    local z, vx = P.z, P.vx
    for b = 1, bins do sum[b], count[b] = 0, 0 end
    for i = 1, #P do
      local b = math.floor(z[i] / height * bins) + 1
      if b >= 1 and b <= bins then sum[b], count[b] = sum[b] + vx[i], count[b] + 1 end
    end
    row[1] = s:time()
    for b = 1, bins do row[b + 1] = count[b] > 0 and sum[b] / count[b] or 0 end
    s:append("profile", row)
    spent = spent + wall_time() - t0
  end }
end
sim:prepare()
local t0 = wall_time()
sim:run { steps = p.steps }
local total = wall_time() - t0
print(string.format("lua_profile: %d particles, %d steps in %.3f s; the Lua diagnostic %.3f s (%.1f %% of the run)",
                    #sim:arrays(), p.steps, total, spent, 100 * spent / total))
