-- The scene that docs/tutorial.md builds step by step: glass beads in a
-- rotating drum (2D), settled under gravity, then turned; it records the
-- height of the pile's centre of mass as a time series and reports the mean
-- kinetic energy. ctest runs it (scene.tutorial_drum), so the tutorial cannot rot.
--
--   build/granule run scenarios/tutorial_drum.lua
--   build/granule run scenarios/tutorial_drum.lua -D rpm=60 -o fast.h5
local granule = require "granule"

-- 1. Parameters: what someone may want to change from the command line (-D name=value).
local p = parameters {
  rpm = { default = 30, unit = "1/min", doc = "drum speed" },
  particles = { default = 100, integer = true, min = 1, max = 300, doc = "number of beads (the fill overlaps them: beads over 3/4 of the drum's area would burst out)" },
  radius = { default = 1e-3, above = 0, unit = "m", doc = "bead radius" },
  drum_radius = { default = 20e-3, above = 0, unit = "m" },
  settle = { default = 0.5, min = 0, unit = "s", doc = "longest time allowed to settle" },
  duration = { default = 1.0, min = 0, unit = "s", doc = "time the drum turns" },
}

-- 2. The simulation and its materials.
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }

-- 3. Contact laws for every pair of materials that can touch.
sim:contact { "glass", "glass", model = "walton_braun", k_load = 2e3, restitution = 0.85, friction = 0.4 }
sim:contact { "glass", "steel", model = "walton_braun", k_load = 2e3, restitution = 0.85, friction = 0.5 }

-- 4. The drum: a cylinder with the beads inside; it starts at rest.
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = p.drum_radius, inside = true,
                    material = "steel" }

-- 5. The beads, placed at random in the drum (a quarter of its area); gravity will pile them up.
-- Beads over 3/4 of its area would start so deep in one another that the first
-- steps throw some through the wall: refused, naming the parameters.
local covered = p.particles * p.radius ^ 2 / p.drum_radius ^ 2
if covered > 0.75 then
  error(string.format("particles = %d of radius %g m cover %.2f of the drum's area (drum_radius = %g m), "
    .. "more than 0.75: fewer or smaller beads, or a larger drum", p.particles, p.radius, covered,
    p.drum_radius), 0)
end
sim:fill { region = { circle = { center = { 0, 0 }, radius = p.drum_radius } }, count = p.particles,
           radius = p.radius, material = "glass", seed = 1 }

-- 6. Gravity along -y.
sim:gravity { 0, -9.81 }

-- 7. Output: snapshots every 10 ms into the HDF5 file (and the .xmf for ParaView).
local file = sim:output { snapshot_every = 0.01 }

-- 8. A measurement of our own: the height of the centre of mass, every millisecond.
sim:series("pile", { "time", "centre_height" })
local function centre_height(s)
  local sum_m, sum_my = 0, 0
  for _, id in ipairs(s:particles()) do
    local b = s:particle(id)
    sum_m = sum_m + b.mass
    sum_my = sum_my + b.mass * b.position[2]
  end
  return sum_my / sum_m
end
sim:every { time = 1e-3, function(s) s:append("pile", { s:time(), centre_height(s) }) end }

-- 8b. A velocity profile at array speed: the mean x-velocity in ten height bins, every 100 steps.
local bins, profile_row, bin_sum, bin_count = 10, {}, {}, {}
local profile_columns, profile_units = { "time" }, { "s" }
for b = 1, bins do
  profile_columns[b + 1], profile_units[b + 1] = "vx_" .. b, "m/s"
end
sim:series("profile", profile_columns, profile_units)
sim:every { steps = 100, function(s)
  local P = s:arrays()
  local y, vx = P.y, P.vx
  for b = 1, bins do bin_sum[b], bin_count[b] = 0, 0 end
  for i = 1, #P do
    local b = math.floor((y[i] + p.drum_radius) / (2 * p.drum_radius) * bins) + 1
    if b >= 1 and b <= bins then
      bin_sum[b], bin_count[b] = bin_sum[b] + vx[i], bin_count[b] + 1
    end
  end
  profile_row[1] = s:time()
  for b = 1, bins do profile_row[b + 1] = bin_count[b] > 0 and bin_sum[b] / bin_count[b] or 0 end
  s:append("profile", profile_row)
end }

-- 9. Settle until the beads are nearly at rest, then turn the drum. Beads let go
-- at rest are calm before they fall: not before a bead from the top of the drum
-- could have fallen its diameter, in sqrt(2 * 2R / g).
local fall_time = math.sqrt(4 * p.drum_radius / 9.81)
-- Nearly at rest: a kinetic energy (spins too) below that of all the beads moving
-- at 10 % of sqrt(g d), whatever their size (granule.calm).
local calm = granule.calm(sim, 0.1 * math.sqrt(9.81 * 2 * p.radius))
granule.stage(sim, { name = "settle", duration = p.settle, check_every = 500,
                     stop_when = function(s) return s:time() > fall_time and calm(s) end })
sim:set_wall("drum", { angular_velocity = granule.rpm(p.rpm) })
local energy, samples = 0, 0
sim:every { steps = 100, function(s)
  energy = energy + s:stats().kinetic_energy
  samples = samples + 1
end }
granule.stage(sim, { name = "rotate", duration = p.duration })

-- 10. Results: a scalar for parameter sweeps, a picture, a summary line.
-- (A run of duration 0, to explore at the REPL, has no samples: no mean then.)
local mean = samples > 0 and energy / samples or nil
if mean then sim:result { mean_kinetic_energy = mean } end
sim:picture { file = file:gsub("%.h5$", "") .. ".png", color_by = "speed" }
print(string.format("tutorial_drum: t = %.3f s, centre height %.4g m, mean kinetic energy %s",
  sim:time(), centre_height(sim), mean and string.format("%.3g J", mean) or "none (no samples)"))
print("results written to " .. file)  -- closed, with a last snapshot, when the program ends
