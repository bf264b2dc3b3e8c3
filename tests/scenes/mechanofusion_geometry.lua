-- granule.mechanofusion's geometry against SPEC 4.1 and 5.3.2 / appendix A,
-- and its refusals of bad input (each naming the parameter).
local mf = require "granule.mechanofusion"

local function near(a, b, what, tol)
  tol = tol or 1e-12
  if math.abs(a - b) > tol * math.max(1, math.abs(b)) then
    error(string.format("%s: got %.15g, expected %.15g", what, a, b), 2)
  end
end

-- Table 4.1 / SPEC 4.1: the inner piece 12.5 - 1.6 - 5 = 5.9 mm from the axis.
local g = mf.geometry {}
near(g.inner_offset, 5.9e-3, "inner offset")
near(g.inner_center[1], 5.9e-3, "inner centre x")
near(g.chamber_radius - g.inner_offset - g.inner_radius, 1.6e-3, "narrowest gap")
assert(g.particles == 1500 and g.depth == 0.4e-3, "Table 4.1 loading and one-diameter depth")
-- The scraper: 4.4 mm of 0.4 mm particles = 11, the first touching the wall,
-- at 100 deg, the row at 70 deg to the wall's tangent (the default), leaning upstream.
assert(#g.scraper_positions == 11, "scraper of 11 particles, got " .. #g.scraper_positions)
local first, last = g.scraper_positions[1], g.scraper_positions[11]
near(math.sqrt(first[1] ^ 2 + first[2] ^ 2), 12.5e-3 - 0.2e-3, "first scraper particle touches the wall")
near(math.deg(math.atan(first[2], first[1])), 100, "scraper position", 1e-9)
local row = { last[1] - first[1], last[2] - first[2] }
local length = math.sqrt(row[1] ^ 2 + row[2] ^ 2)
near(length, 10 * 0.4e-3, "row length")
local tangent = { -math.sin(math.rad(100)), math.cos(math.rad(100)) }   -- the wall's motion
local cos_to_tangent = (row[1] * tangent[1] + row[2] * tangent[2]) / length
near(math.deg(math.acos(-cos_to_tangent)), 70, "tilt to the tangent, against the motion", 1e-9)
for _, x in ipairs(g.scraper_positions) do
  assert(math.sqrt(x[1] ^ 2 + x[2] ^ 2) <= 12.5e-3 - 0.2e-3 + 1e-12, "scraper inside the chamber")
end

-- 5.3.2: all machine lengths x2, gap 3.2 mm, 4x the particles, particles unchanged.
local d = mf.geometry { size_scale = 2 }
near(d.chamber_radius, 25e-3, "double chamber")
near(d.gap, 3.2e-3, "double gap")
near(d.inner_offset, 2 * 5.9e-3, "double inner offset")
assert(d.particles == 6000 and d.radius == 0.2e-3 and #d.scraper_positions == 22, "double loading and scraper")

-- Appendix A: 4 diameters of slab, 6000 particles, the scraper in 4 rows.
local s = mf.geometry { dimension = 3 }
near(s.depth, 1.6e-3, "slab depth")
assert(s.particles == 6000, "slab loading")
local sim3, g3 = mf.build { dimension = 3, particles = 20 }
assert(#g3.scraper_ids == 44 and sim3:dimension() == 3, "4 scraper rows in 3D")
assert(#g3.particle_ids == 80, "4x 20 particles in the slab")

local sim2, g2 = mf.build { scraper = false, particles = 30 }
assert(#g2.scraper_ids == 0 and #g2.particle_ids == 30 and mf.escaped(sim2, g2) == 0, "without scraper")

-- Refusals name the parameter.
local function refused(p, word)
  local ok, message = pcall(mf.geometry, p)
  assert(not ok, "accepted a bad " .. word)
  assert(tostring(message):find(word, 1, true), "message does not name " .. word .. ": " .. tostring(message))
end
refused({ gap = 8e-3 }, "inner_radius + gap")
refused({ gap = 0.3e-3 }, "gap")
refused({ dimension = 4 }, "dimension")
refused({ radius = -1 }, "radius")
refused({ scraper_tilt = 95 }, "scraper_tilt")
refused({ area_free_from = 30 }, "area bounds")
refused({ particles = 10.5 }, "particles")
print("mechanofusion geometry ok")
