-- The Mechanofusion studies of dissertation chapters 4-5 and appendix A, one
-- scene looping over cases (docs/mechanofusion.md):
--   study=scraper    with vs without scraper (4.3): patterns, zone profiles
--   study=rpm        inner-piece force and area forces vs speed, 500-4000 rpm
--                    (Figs. 4.16, 5.3, 4.32, 5.11-5.12)
--   study=loading    inner-piece force vs loading at three speeds (4.17-4.18)
--   study=gap        area forces vs gap (4.34, 5.13)
--   study=stiffness  area forces vs K1 (5.8-5.10)
--   study=double     double-sized system vs the original (5.3.2, 5.4-5.7)
--   study=slab       3D periodic slab vs 2D (A.1-A.6)
-- Each case: build, run `settle` without diagnostics (the start from a
-- random overlapping fill), then `measure` with all diagnostics attached.
-- Full length (the dissertation's times: 10 s, 2 s windows) takes hours;
-- -D short=true runs each case for a few chamber revolutions instead.
--
--   granule run scenarios/mechanofusion_study.lua -D study=rpm -D short=true
--   /usr/bin/python3 tools/plot_mechanofusion.py study mechanofusion_rpm.h5
--
-- Writes <out> (default mechanofusion_<study>.h5): /cases (one row per case)
-- and /profiles (one row per case and zone); each case also writes its own
-- <out without .h5>_case<k>.h5 with the diagnostics' time series.
local mf = require "granule.mechanofusion"
local checks = require "granule.checks"

local p = parameters(mf.parameter_spec {
  study = { default = "rpm", doc = "scraper | rpm | loading | gap | stiffness | double | slab" },
  short = { default = false, doc = "a few revolutions per case instead of the dissertation's times" },
  values = { default = "", doc = "override the study's list of values, comma-separated" },
  speeds = { default = "1000,2000,4000", unit = "1/min", doc = "the three speeds of study=loading" },
  settle = { default = 0, unit = "s", doc = "override: time before measuring (0: the study's)" },
  measure = { default = 0, unit = "s", doc = "override: measuring time (0: the study's)" },
  settle_revolutions = { default = 2, unit = "-", doc = "short runs: settle this many revolutions" },
  measure_revolutions = { default = 2, unit = "-", doc = "short runs: measure this many revolutions" },
  pictures = { default = 4, unit = "-", doc = "study=scraper: pattern pictures per case" },
  out = { default = "", doc = "output file (default mechanofusion_<study>.h5)" },
})

local function numbers(text, name)
  local list = {}
  for item in text:gmatch("[^,%s]+") do
    local value = tonumber(item)
    if not value then error(string.format("%s: '%s' is not a number", name, item)) end
    list[#list + 1] = value
  end
  return list
end

-- Each study: the cases (overrides of the base parameters) and the
-- dissertation's run times (settle, measure) for the full version: every
-- study settles 0.5 s before its diagnostics are attached (the overlapping
-- fill's first revolution would otherwise count in them).
local studies = {
  scraper = { key = "scraper", values = { 1, 0 }, full = { 0.5, 10 } },
  rpm = { key = "rpm", values = { 500, 1000, 2000, 3000, 4000 }, full = { 0.5, 2 } },
  loading = { key = "particles", values = { 500, 1000, 1500, 2000 }, full = { 0.5, 2 } },
  gap = { key = "gap", values = { 1.0e-3, 1.6e-3, 2.4e-3, 3.2e-3 }, full = { 0.5, 2 } },
  stiffness = { key = "k_load", values = { 2000, 5000, 20000, 50000 }, full = { 0.5, 2 } },
  double = { key = "size_scale", values = { 1, 2 }, full = { 0.5, 1 } },
  slab = { key = "dimension", values = { 2, 3 }, full = { 0.5, 1 } },
}
local study = studies[p.study]
if not study then
  local names = {}
  for k in pairs(studies) do names[#names + 1] = k end
  table.sort(names)
  error(string.format("study: '%s' is not one of %s", p.study, table.concat(names, ", ")))
end
local values = p.values ~= "" and numbers(p.values, "values") or study.values

-- The study's own -D values, checked before any case is built or run.
local where = "mechanofusion_study"
checks.non_negative(where, "settle", p.settle, "s")
checks.non_negative(where, "measure", p.measure, "s")
checks.non_negative(where, "settle_revolutions", p.settle_revolutions)
checks.positive(where, "measure_revolutions", p.measure_revolutions)
if p.pictures < 0 or p.pictures ~= math.floor(p.pictures) then
  checks.fail(where, "pictures", "a whole number >= 0", p.pictures)
end
if #values == 0 then checks.fail(where, "values", "at least one number", p.values) end
for _, v in ipairs(values) do
  if p.study == "slab" then
    if v ~= 2 and v ~= 3 then checks.fail(where, "values", "2 or 3 (dimensions)", v) end
  elseif p.study == "rpm" then
    checks.non_negative(where, "values", v, "1/min")  -- a chamber at rest is a case too
  elseif p.study ~= "scraper" then
    checks.positive(where, "values", v, mf.defaults[study.key].unit)
  end
end

local cases = {}
if p.study == "loading" then
  for _, rpm in ipairs(numbers(p.speeds, "speeds")) do
    checks.positive(where, "speeds", rpm, "1/min")
    for _, n in ipairs(values) do cases[#cases + 1] = { particles = n, rpm = rpm } end
  end
else
  for _, v in ipairs(values) do
    local c = {}
    if study.key == "scraper" then c.scraper = v ~= 0 else c[study.key] = v end
    cases[#cases + 1] = c
  end
end
-- Every case's machine checked now (mf.geometry builds nothing), not when its turn comes;
-- a short run counts revolutions, which a chamber at rest never makes.
for _, case in ipairs(cases) do
  local values_k = {}
  for name, v in pairs(p) do values_k[name] = v end
  for name, v in pairs(case) do values_k[name] = v end
  local geo = mf.geometry(values_k)
  if p.short and not (geo.rpm > 0) then checks.fail(where, "rpm", "> 0 1/min with short=true", geo.rpm) end
end

local out = p.out ~= "" and p.out or ("mechanofusion_" .. p.study .. ".h5")
local stem = out:gsub("%.h5$", "")
local record = simulation { dimension = 2 }
local written = record:output { file = out, xdmf = false }
if written ~= out then
  error(string.format("the study writes one file per case, named after -D out=; -o %s would make "
    .. "them all the same file: use -D out=%s instead", written, written))
end
local case_columns = { "case", "rpm", "gap", "k_load", "particles", "size_scale", "dimension", "scraper",
                       "settle", "measure", "inner_normal_force", "inner_tangential_force" }
local per_area = { "normal_force_per_particle", "tangential_force_per_particle", "normal_force_per_contact",
                   "tangential_force_per_contact", "particles", "collision_ratio_particle",
                   "collision_ratio_boundary", "mean_peak_force", "fraction_over_200_mm_s" }
for _, q in ipairs(per_area) do
  for _, a in ipairs(mf.area_names) do case_columns[#case_columns + 1] = q .. "_" .. a end
end
-- The flow in the narrow gap sector (5.2), the deepest contacts, the readings of 4.7.
local extra_columns = { "gap_shear_rate", "gap_nominal_shear_rate", "gap_mean_granular_temperature",
                        "gap_mean_solid_fraction", "gap_normal_force_per_contact", "max_overlap_ratio_particle",
                        "max_overlap_ratio_fixed", "max_overlap_ratio_wall" }
for _, c in ipairs(mf.coating_readings) do extra_columns[#extra_columns + 1] = "coating_time_estimate_" .. c end
for _, c in ipairs(extra_columns) do case_columns[#case_columns + 1] = c end
for _, c in ipairs { "coating_time_estimate", "covered_fraction", "escaped", "wall_seconds" } do
  case_columns[#case_columns + 1] = c
end
record:series("cases", case_columns)
local profile_quantities = { "rotational_ke", "deviatoric_ke", "deviatoric_ke_cartesian", "pressure",
                             "pressure_kinetic", "pressure_virial", "collision_work_rate", "solid_fraction",
                             "count" }
local profile_columns = { "case", "zone", "r_inner", "r_outer" }
for _, q in ipairs(profile_quantities) do profile_columns[#profile_columns + 1] = q end
record:series("profiles", profile_columns)

for k, case in ipairs(cases) do
  local values_k = {}
  for name, v in pairs(p) do values_k[name] = v end
  for name, v in pairs(case) do values_k[name] = v end
  local sim, geo = mf.build(values_k)
  local revolution = 60 / geo.rpm
  local settle, measure
  if p.short then
    settle, measure = p.settle_revolutions * revolution, p.measure_revolutions * revolution
  else
    settle, measure = study.full[1], study.full[2]
  end
  if p.settle > 0 then settle = p.settle end
  if p.measure > 0 then measure = p.measure end
  local start = wall_time()
  sim:output { file = string.format("%s_case%d.h5", stem, k), snapshot_every = 0, series_every = measure / 50,
               xdmf = false }
  if settle > 0 then sim:run { duration = settle } end
  local ids = mf.attach_diagnostics(sim, geo, { window = measure / 20, every = 10 })
  if p.study == "scraper" and p.pictures > 0 then
    local times = {}
    for j = 1, p.pictures do times[j] = measure * j / p.pictures end
    mf.run_with_pictures(sim, measure, times, string.format("%s_%s", stem, geo.scraper and "with" or "without"))
  else
    sim:run { duration = measure }
  end
  local s = mf.summary(sim, geo, ids)
  s.escaped = mf.escaped(sim, geo, geo.radius)
  mf.record(sim, s)
  local row = { k, geo.rpm, geo.gap, geo.values.k_load, geo.particles, geo.values.size_scale, geo.dimension,
                geo.scraper and 1 or 0, settle, measure, s.inner_normal_force, s.inner_tangential_force }
  for _, q in ipairs(per_area) do
    for _, a in ipairs(mf.area_names) do row[#row + 1] = s[q .. "_" .. a] end
  end
  for _, c in ipairs(extra_columns) do row[#row + 1] = s[c] or 0 end
  row[#row + 1] = s.coating_time_estimate
  row[#row + 1] = s.covered_fraction
  row[#row + 1] = s.escaped
  row[#row + 1] = wall_time() - start
  record:append("cases", row)
  local radii = sim:diagnostic_results(ids.zones).zone_radii
  for z = 1, #s.profiles.count do
    local prow = { k, z, radii[z], radii[z + 1] }
    for _, q in ipairs(profile_quantities) do prow[#prow + 1] = s.profiles[q][z] end
    record:append("profiles", prow)
  end
  sim:close()
  print(string.format("case=%d %s rpm=%g gap=%g k_load=%g particles=%d size_scale=%g dimension=%d scraper=%s "
    .. "settle=%.4g measure=%.4g inner_normal=%.4g inner_tangential=%.4g contact_normal_inner_piece=%.4g "
    .. "contact_normal_scraper=%.4g escaped=%d wall=%.1fs", k, p.study, geo.rpm, geo.gap, geo.values.k_load,
    geo.particles, geo.values.size_scale, geo.dimension, tostring(geo.scraper), settle, measure,
    s.inner_normal_force, s.inner_tangential_force, s.normal_force_per_contact_inner_piece,
    s.normal_force_per_contact_scraper, s.escaped, wall_time() - start))
end
record:result { cases = #cases, short = p.short and 1 or 0 }
record:close()
print("study written to " .. out)
