-- Deformation study of dissertation section 4.6 (Figs 4.27-4.30) with the
-- appendix B chain of granule.coating: PMMA hosts of 400 um meeting at a
-- relative velocity v, Al2O3 guests of 5 um between them (Table 4.2).
--
-- Writes three series to HDF5 and prints one summary line:
--   /velocity    impact_velocity, contact_area (Fig. 4.27), max_contact_radius,
--                total_force, force_per_guest, ratio_hertz, ratio_jkr (Fig. 4.28),
--                ratio_jkr_hard (the harder host of Fig. 4.30)
--   /guest_size  guest_diameter, ratio_hertz, ratio_jkr (Fig. 4.29) at `velocity`
--   /hardness    host_young, ratio_hertz, ratio_jkr at `velocity` (Fig. 4.30 as a sweep)
-- No particles are simulated: the numbers are closed-form (appendix B).
--
--   granule run scenarios/coating_deformation.lua -o coating_deformation.h5
--   /usr/bin/python3 tools/plot_coating_deformation.py coating_deformation.h5 -o coating_deformation.png
local coating = require "granule.coating"
local materials = require "granule.materials"
local granule = require "granule"
local checks = require "granule.checks"

local p = parameters {
  host = { default = "PMMA", doc = "host material (granule.materials)" },
  guest = { default = "Al2O3", doc = "guest material" },
  host_radius = { default = 200e-6, above = 0, unit = "m", doc = "host radius (400 um diameter, 4.6)" },
  guest_radius = { default = 2.5e-6, above = 0, unit = "m", doc = "guest radius (5 um diameter, 4.6)" },
  velocity = { default = 1.0, above = 0, unit = "m/s", doc = "relative impact velocity of the guest-size and hardness sweeps" },
  velocity_min = { default = 0.01, above = 0, unit = "m/s", doc = "first velocity of the velocity sweep" },
  velocity_max = { default = 10, above = 0, unit = "m/s", doc = "last velocity of the velocity sweep" },
  guest_diameter_min = { default = 0.5e-6, above = 0, unit = "m", doc = "smallest guest of the size sweep" },
  guest_diameter_max = { default = 20e-6, above = 0, unit = "m", doc = "largest guest of the size sweep" },
  hard_host_young = { default = 6.6e9, above = 0, unit = "Pa", doc = "Young's modulus of the harder host (Fig. 4.30)" },
  young_min = { default = 1e9, above = 0, unit = "Pa", doc = "first host modulus of the hardness sweep" },
  young_max = { default = 30e9, above = 0, unit = "Pa", doc = "last host modulus of the hardness sweep" },
  packing_ratio = { default = coating.DEFAULT_PACKING_RATIO, above = 0, max = 1, unit = "-", doc = "guest coverage (B.6), in (0, 1]" },
  points = { default = 41, integer = true, min = 2, max = 10000, unit = "-", doc = "points per sweep (log-spaced)" },
}

assert(p.points >= 2 and p.points == math.floor(p.points), "points must be a whole number >= 2")
-- The -D values first, by their names here (granule.coating names its own arguments).
for _, name in ipairs { "host_radius", "guest_radius", "guest_diameter_min", "guest_diameter_max" } do
  checks.positive("coating_deformation", name, p[name], "m")
end
for _, name in ipairs { "velocity", "velocity_min", "velocity_max" } do
  checks.positive("coating_deformation", name, p[name], "m/s")
end
for _, name in ipairs { "hard_host_young", "young_min", "young_max" } do
  checks.positive("coating_deformation", name, p[name], "Pa")
end
local hard_name = p.host .. "_hard"
materials.define { name = hard_name, base = p.host, young_modulus_pa = p.hard_host_young }

local function log_space(first, last, count)
  local values = {}
  for k = 0, count - 1 do values[#values + 1] = first * (last / first) ^ (k / (count - 1)) end
  return values
end

local function deformation(host, guest_radius, velocity)
  return coating.guest_deformation { host = host, guest = p.guest, host_radius_m = p.host_radius,
                                     guest_radius_m = guest_radius, impact_velocity_m_s = velocity,
                                     packing_ratio = p.packing_ratio }
end

-- A simulation object only to own the output file (provenance: scene, parameters).
local record = simulation { dimension = 2 }
local out = record:output {}

record:series("velocity", { "impact_velocity", "contact_area", "max_contact_radius", "total_force",
                            "force_per_guest", "ratio_hertz", "ratio_jkr", "ratio_jkr_hard" })
for _, v in ipairs(log_space(p.velocity_min, p.velocity_max, p.points)) do
  local d = deformation(p.host, p.guest_radius, v)
  local hard = deformation(hard_name, p.guest_radius, v)
  record:append("velocity", { v, d.contact_area_m2, d.max_contact_radius_m, d.total_force_n, d.force_per_guest_n,
                              d.hertz_central_displacement_ratio, d.jkr_central_displacement_ratio,
                              hard.jkr_central_displacement_ratio })
end

record:series("guest_size", { "guest_diameter", "ratio_hertz", "ratio_jkr" })
for _, diameter in ipairs(log_space(p.guest_diameter_min, p.guest_diameter_max, p.points)) do
  local d = deformation(p.host, diameter / 2, p.velocity)
  record:append("guest_size", { diameter, d.hertz_central_displacement_ratio, d.jkr_central_displacement_ratio })
end

record:series("hardness", { "host_young", "ratio_hertz", "ratio_jkr" })
for _, young in ipairs(log_space(p.young_min, p.young_max, p.points)) do
  local name = p.host .. "_sweep"
  materials.define { name = name, base = p.host, young_modulus_pa = young }
  local d = deformation(name, p.guest_radius, p.velocity)
  record:append("hardness", { young, d.hertz_central_displacement_ratio, d.jkr_central_displacement_ratio })
end

local base = deformation(p.host, p.guest_radius, p.velocity)
local hard = deformation(hard_name, p.guest_radius, p.velocity)
local summary = {
  limiting_elastic_velocity = base.limiting_elastic_velocity_m_s,
  velocity = p.velocity,
  contact_area = base.contact_area_m2,
  force_per_guest = base.force_per_guest_n,
  work_of_adhesion = base.work_of_adhesion_j_m2,
  ratio_hertz = base.hertz_central_displacement_ratio,
  ratio_jkr = base.jkr_central_displacement_ratio,
  ratio_jkr_hard = hard.jkr_central_displacement_ratio,
}
record:result(summary)
record:close()
print(granule.summary_line(summary, { "limiting_elastic_velocity", "velocity", "contact_area", "force_per_guest",
  "work_of_adhesion", "ratio_hertz", "ratio_jkr", "ratio_jkr_hard" }))
io.stderr:write("wrote " .. out .. "\n")
