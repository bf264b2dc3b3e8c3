-- A short Mechanofusion-like demo (the README's default scene): the 2D
-- system of dissertation Table 4.1 -- 1500 PMMA-like particles in a 25 mm
-- chamber spinning at 2000 rpm, a stationary 10 mm inner piece leaving a
-- 1.6 mm gap, and a scraper of fixed particles -- run for a fraction of a
-- second with Walton-Braun contacts. Geometry choices follow SPEC 4.1.
--
--   granule run scenarios/mechanofusion_demo.lua -D duration=0.05
--   /usr/bin/python3 tools/plot_pattern.py mechanofusion_demo.h5
local granule = require "granule"

local p = parameters {
  duration = { default = 0.01, min = 0, unit = "s", doc = "simulated time" },
  particles = { default = 1500, integer = true, min = 1, max = 1e6, doc = "number of powder particles" },
  rpm = { default = 2000, unit = "1/min", doc = "chamber speed" },
  radius = { default = 0.2e-3, above = 0, unit = "m" },
  density = { default = 1200, above = 0, unit = "kg/m^3" },
  chamber_radius = { default = 12.5e-3, above = 0, unit = "m" },
  inner_radius = { default = 5e-3, above = 0, unit = "m" },
  gap = { default = 1.6e-3, above = 0, unit = "m", doc = "narrowest gap between inner piece and chamber" },
  k_load = { default = 20000, above = 0, unit = "N/m" },
  restitution = { default = 0.85 , above = 0, max = 1},
  friction_particle = { default = 0.4 , min = 0},
  friction_wall = { default = 0.5 , min = 0},
  scraper = { default = true, doc = "add the scraper (a row of fixed particles)" },
  scraper_angle = { default = 100, unit = "deg", doc = "position downstream of the inner piece" },
  scraper_tilt = { default = 70, unit = "deg", doc = "angle to the wall's tangent (70 jams no particle against the wall: docs/mechanofusion.md)" },
  scraper_length = { default = 4.4e-3, above = 0, unit = "m" },
  seed = { default = 1 , integer = true},
  snapshot_every = { default = 0.002, min = 0, unit = "s" },
}
assert(p.inner_radius + p.gap < p.chamber_radius, string.format("inner_radius + gap (%g m) must be below chamber_radius (%g m): the inner piece must fit in the chamber", p.inner_radius + p.gap, p.chamber_radius))

local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = p.density }
sim:material { name = "steel", density = 7800 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = p.k_load,
              restitution = p.restitution, friction = p.friction_particle }
sim:contact { "powder", "steel", model = "walton_braun", k_load = p.k_load,
              restitution = p.restitution, friction = p.friction_wall }
-- The scraper is powder-sized fixed particles with the wall's friction (4.2.1; 4.5
-- counts them as solid boundary), as granule.mechanofusion builds it.
sim:material { name = "scraper", density = p.density }
sim:contact { "powder", "scraper", model = "walton_braun", k_load = p.k_load,
              restitution = p.restitution, friction = p.friction_wall }

local omega = granule.rpm(p.rpm)
local inner_offset = p.chamber_radius - p.gap - p.inner_radius   -- 5.9 mm (SPEC 4.1)
-- The inner piece sits at angle 0; the chamber turns counter-clockwise.
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = p.chamber_radius, inside = true,
                    angular_velocity = omega, material = "steel" }
sim:wall_cylinder { name = "inner_piece", center = { inner_offset, 0 }, radius = p.inner_radius,
                    inside = false, material = "steel" }

if p.scraper then
  -- A row of fixed powder-sized particles touching the wall (zero clearance),
  -- leaning into the flow at `scraper_tilt` to the wall's tangent.
  local phi = math.rad(p.scraper_angle)
  local outward = granule.vec.polar(phi)
  local tangent = granule.vec.polar(phi + math.pi / 2)   -- direction of the wall's motion
  local first = granule.vec.scale(outward, p.chamber_radius - p.radius)
  local tilt = math.rad(p.scraper_tilt)
  -- inward and upstream, so the flow meets the blade's face
  local direction = granule.vec.add(granule.vec.scale(outward, -math.sin(tilt)),
                                    granule.vec.scale(tangent, -math.cos(tilt)))
  local count = math.floor(p.scraper_length / (2 * p.radius) + 0.5)
  for _, x in ipairs(granule.particle_row(first, direction, count, p.radius)) do
    sim:add_particle { position = x, radius = p.radius, material = "scraper", fixed = true }
  end
end

sim:fill { region = { circle = { center = { 0, 0 }, radius = p.chamber_radius } },
           count = p.particles, radius = p.radius, material = "powder", seed = p.seed,
           max_speed = 0.01 }

local file = sim:output { snapshot_every = p.snapshot_every, series_every = 1e-4 }
-- Force on the inner piece (4.4.1), averaged over 1 ms windows into /diagnostics.
local inner_force = sim:diagnostic("wall_force", { wall = "inner_piece", window = 1e-3 })
sim:snapshot()
local result = sim:run { duration = p.duration }
local s = sim:stats()
local inner = sim:diagnostic_results(inner_force)
print(string.format("t=%.4g s steps=%d dt=%.4g s kinetic_energy=%.4g J contacts=%d "
  .. "inner_piece_normal_force=%.4g N inner_piece_tangential_force=%.4g N",
  s.time, result.steps, sim:time_step(), s.kinetic_energy, s.contacts_particle + s.contacts_wall,
  inner.mean_normal_force, inner.mean_tangential_force))
sim:close()
print("results written to " .. file)
