-- The Mechanofusion system of dissertation chapter 4, configurable: Table 4.1
-- by default (1500 particles of r = 0.2 mm in a 25 mm chamber at 2000 rpm,
-- 10 mm inner piece, 1.6 mm gap, scraper, Walton-Braun), every number a -D
-- parameter (see lua/granule/mechanofusion.lua and docs/mechanofusion.md).
-- Attaches the diagnostics of 4.3-4.5 and 7.2: force on the inner piece,
-- radial zones, four areas, contact peaks and coating time; writes them to
-- HDF5 under /diagnostics and the long-time means to /results.
--
--   granule run scenarios/mechanofusion.lua -D duration=0.1
--   granule run scenarios/mechanofusion.lua -D scraper=false -D duration=0.1 -D pictures=0.05,0.1
--   granule run scenarios/mechanofusion.lua -D dimension=3          # the periodic slab of app. A
--   granule run scenarios/mechanofusion.lua -D size_scale=2         # the double-sized system (5.3.2)
--   /usr/bin/python3 tools/plot_mechanofusion.py series mechanofusion.h5   # areas, inner piece vs time
--   /usr/bin/python3 tools/plot_mechanofusion.py peaks mechanofusion.h5    # contact peaks (Figs. 7.1-7.8)
-- (the zone profiles: the printed 'zones' lines; drawn by `study` from mechanofusion_study.lua's file)
local mf = require "granule.mechanofusion"
local checks = require "granule.checks"

local p = parameters(mf.parameter_spec {
  duration = { default = 0.02, unit = "s", doc = "simulated time" },
  settle = { default = 0, unit = "s", doc = "run this long before attaching the diagnostics (the start's overlapping fill inflates the coating sum)" },
  pictures = { default = "", unit = "s", doc = "pattern pictures at these times, comma-separated (Figs. 4.6-4.7)" },
  picture_prefix = { default = "mechanofusion", doc = "picture files: <prefix>_<ms>ms.png (<us>us when two times share a ms)" },
  snapshot_every = { default = 0, unit = "s", doc = "particle snapshots this often (0: first and last)" },
  keep_collisions = { default = 0, unit = "-", doc = "host-host collisions kept for coating.minimum_time" },
})

-- The scene's own -D values, checked before anything is built or run.
checks.positive("mechanofusion", "duration", p.duration, "s")
checks.non_negative("mechanofusion", "settle", p.settle, "s")
local times = {}
for item in p.pictures:gmatch("[^,%s]+") do
  local t = tonumber(item)
  if not t then error("pictures: '" .. item .. "' is not a number") end
  if not (t >= 0 and t <= p.duration) then
    error(string.format("pictures: %s s is outside the run: each time must be in [0, duration = %g] s", item, p.duration))
  end
  times[#times + 1] = t
end
mf.picture_files(times, p.picture_prefix)  -- refuses two times that would write one file

local sim, geo = mf.build(p)
local file = sim:output { snapshot_every = p.snapshot_every, series_every = 1e-3 }
if p.settle > 0 then sim:run { duration = p.settle } end
local ids = mf.attach_diagnostics(sim, geo, { keep_collisions = p.keep_collisions })
sim:snapshot()
mf.run_with_pictures(sim, p.duration, times, p.picture_prefix)

local s = mf.summary(sim, geo, ids)
local escaped = mf.escaped(sim, geo)
local stats = sim:stats()
s.escaped = escaped
s.particles_now = stats.particles - #geo.scraper_ids
mf.record(sim, s)

print(string.format("mechanofusion dimension=%d particles=%d rpm=%g gap=%g scraper=%s t=%.4g s dt=%.4g s",
  geo.dimension, geo.particles, geo.rpm, geo.gap, tostring(geo.scraper), sim:time(), sim:time_step()))
print(string.format("inner_piece_normal_force=%.5g N inner_piece_tangential_force=%.5g N",
  s.inner_normal_force, s.inner_tangential_force))
for _, a in ipairs(mf.area_names) do
  print(string.format("area=%s normal_per_particle=%.4g N normal_per_contact=%.4g N tangential_per_contact=%.4g N "
    .. "particles=%.4g collision_ratio_particle=%.4g collision_ratio_boundary=%.4g", a,
    s["normal_force_per_particle_" .. a], s["normal_force_per_contact_" .. a],
    s["tangential_force_per_contact_" .. a], s["particles_" .. a], s["collision_ratio_particle_" .. a],
    s["collision_ratio_boundary_" .. a]))
end
print(string.format("overlaps max_overlap_ratio particle=%.4g fixed=%.4g wall=%.4g deepest_at=(%.4g,%.4g) m t=%.4g s",
  s.max_overlap_ratio_particle, s.max_overlap_ratio_fixed, s.max_overlap_ratio_wall, s.deepest_x or 0,
  s.deepest_y or 0, s.deepest_time or 0))
if s.gap_shear_rate then
  print(string.format("gap sector=+-%g deg shear_rate=%.4g 1/s nominal_shear_rate=%.4g 1/s granular_temperature=%.4g m^2/s^2 "
    .. "solid_fraction=%.4g particles=%.4g normal_per_contact=%.4g N", p.gap_sector, s.gap_shear_rate,
    s.gap_nominal_shear_rate, s.gap_mean_granular_temperature, s.gap_mean_solid_fraction, s.gap_particles,
    s.gap_normal_force_per_contact))
else
  print("gap: not measured (the gap_profile diagnostic needs a cylinder inner piece)")
end
local function list(values) local t = {} for k, v in ipairs(values) do t[k] = string.format("%.4g", v) end return table.concat(t, ",") end
for _, q in ipairs { "solid_fraction", "rotational_ke", "deviatoric_ke", "pressure", "collision_work_rate" } do
  print(string.format("zones %s=%s", q, list(s.profiles[q])))
end
if p.keep_collisions > 0 then
  -- 4.7 through the Lua implementation, fed by the diagnostic's kept collisions.
  local coating = require "granule.coating"
  local r = sim:diagnostic_results(ids.peaks)
  local collisions = {}
  for k = 1, #r.collision_time do
    collisions[k] = { time_s = r.collision_time[k], max_overlap_m = r.collision_overlap[k],
                      effective_radius_m = r.collision_radius[k] }
  end
  -- Each reading of 4.7 twice: the C++ sum and the Lua one over the same
  -- collisions (all of them kept, or up to the coverage) must agree.
  local complete = #collisions < p.keep_collisions
  local readings = { one_patch_rstar = { 1, "effective" }, two_patches_rstar = { 2, "effective" },
                     one_patch_r = { 1, "host" }, two_patches_r = { 2, "host" } }
  local agree = true
  for _, name in ipairs(mf.coating_readings) do
    local t, message, details = coating.minimum_time { collisions = collisions, host_count = geo.particles,
      host_radius_m = geo.radius, patches_per_contact = readings[name][1], contact_radius = readings[name][2] }
    details = t and message or details
    local own = r["covered_fraction_" .. name] * details.target_area_m2
    local same = math.abs(details.covered_area_m2 - own) <= 1e-9 * own
    agree = agree and same
    print(string.format("coating.minimum_time %s=%s covered=%.6g of %.6g m^2 (%s)%s", name, tostring(t),
      details.covered_area_m2, details.target_area_m2, t and "reached" or "not reached in this run",
      (complete and not t and not same) and string.format(" (differs from the diagnostic's by %.3g)",
        math.abs(details.covered_area_m2 - own) / own) or ""))
  end
  if complete and r.coating_reached == 0 then
    print("coating_sums_agree=" .. (agree and "yes" or "no"))
  end
end
print(string.format("coating_time_estimate=%.4g s covered_fraction=%.4g escaped=%d particles_now=%d zone_volume_sum=%.6g chamber_volume=%.6g",
  s.coating_time_estimate, s.covered_fraction, escaped, s.particles_now, s.zone_volume_sum, s.chamber_volume))
sim:close()
print("results written to " .. file)
