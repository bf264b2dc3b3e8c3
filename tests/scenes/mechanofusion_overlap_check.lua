-- The base case pinches nothing: with Table 4.1's stiffness and the default
-- scraper, no contact with the scraper or a wall in a short run at 2000 rpm
-- goes deeper than 2 % of a radius (the dissertation's deformations stay
-- below 1 % of a diameter, 5.4.2). The scraper as SPEC 4.1 first built it
-- (-D scraper_tilt=40) jams a particle in its wedge with the wall at 30-45 %
-- of a radius, and this check then fails. Particle-particle collisions are
-- the flow's own (their depth is the impact speed times sqrt(m*/K1), about
-- 0.5 % of a radius per m/s here): printed, not limited.
-- Prints "mechanofusion overlap check ok".
local mf = require "granule.mechanofusion"

local p = parameters(mf.parameter_spec {
  settle = { default = 0.01, unit = "s", doc = "before measuring (the random fill's first overlaps)" },
  duration = { default = 0.02, unit = "s", doc = "measured" },
  limit = { default = 0.02, unit = "-", doc = "largest overlap allowed, a fraction of the radius" },
})

local sim, geo = mf.build(p)
sim:run { duration = p.settle }
local id = sim:diagnostic("overlaps", { every = 40 })
sim:run { duration = p.duration }
local r = sim:diagnostic_results(id)
local failures = {}
print(string.format("deepest particle contact: %.4g of a radius", r.max_overlap_ratio_particle))
for _, kind in ipairs { "fixed", "wall" } do
  local ratio = r["max_overlap_ratio_" .. kind]
  print(string.format("deepest %s contact: %.4g of a radius", kind, ratio))
  if not (ratio < p.limit) then
    failures[#failures + 1] = string.format("a %s contact reached %.3g of a radius (limit %g) at (%.4g, %.4g) m, "
      .. "%.4g mm from the axis, t = %.4g s", kind, ratio, p.limit, r.deepest_x, r.deepest_y,
      1e3 * math.sqrt(r.deepest_x ^ 2 + r.deepest_y ^ 2), r.deepest_time)
  end
end
if not (r.samples > 0 and r.max_overlap_ratio > 0) then failures[#failures + 1] = "the diagnostic saw no contact" end
if #failures > 0 then error("mechanofusion overlap check failed:\n  " .. table.concat(failures, "\n  ")) end
print(string.format("mechanofusion overlap check ok (scraper_tilt = %g deg)", geo.values.scraper_tilt))
