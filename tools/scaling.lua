-- Kinetic-theory scaling of a Mechanofusion scene (dissertation chapter 5):
-- solid fraction, G and J (Table 5.1), granular temperature and stresses of
-- simple shear (5.4-5.5), the stiffness bounds of 5.12 and 5.15, the
-- recommended stiffness range and the time step (Eq. 4.1) it implies.
-- Parameter names are those of scenarios/mechanofusion_demo.lua, so a scene's
-- -D options can be passed here unchanged.
--
--   granule run tools/scaling.lua                                 # Table 4.1 at 2000 rpm
--   granule run tools/scaling.lua -D rpm=4000 -D gap=1.6e-3       # the case of 5.4.2
--   granule run tools/scaling.lua -D rpm=4000 -D compare_rpm=2000 # plus the similarity ratio 5.11
--
-- The similarity ratio (Eq. 5.11) compares this system with a second one that
-- differs by the compare_* parameters given (0 = same as this system).
local kinetic = require "granule.kinetic"

local p = parameters {
  particles = { default = 1500, unit = "-", doc = "number of particles N" },
  radius = { default = 0.2e-3, unit = "m", doc = "particle radius" },
  density = { default = 1200, unit = "kg/m^3", doc = "particle density" },
  chamber_radius = { default = 12.5e-3, unit = "m", doc = "chamber radius R" },
  inner_radius = { default = 5e-3, unit = "m", doc = "inner piece radius" },
  gap = { default = 1.6e-3, unit = "m", doc = "narrowest gap H" },
  rpm = { default = 2000, unit = "1/min", doc = "chamber speed" },
  restitution = { default = 0.85, unit = "-", doc = "coefficient of restitution e" },
  k_load = { default = 20000, unit = "N/m", doc = "the scene's loading stiffness K (0: none)" },
  young = { default = 3.3e9, unit = "Pa", doc = "Young's modulus for Eq. 4.2 (0: no upper K)" },
  depth = { default = 0, unit = "m", doc = "slab depth of the volume (0: one diameter, 2D)" },
  steps_per_contact = { default = 40, unit = "-", doc = "n of Eq. 4.1" },
  safety_factor = { default = 10, unit = "-", doc = "how much larger '>>' means in 5.12 and 5.15" },
  max_deformation = { default = 0.01, unit = "-", doc = "largest overlap / diameter" },
  impact_velocity = { default = 0, unit = "m/s", doc = "impact speed for the deformation bound (0: 4 (T/pi)^(1/2))" },
  compare_rpm = { default = 0, unit = "1/min", doc = "second system's speed for Eq. 5.11 (0: same)" },
  compare_gap = { default = 0, unit = "m", doc = "second system's gap (0: same)" },
  compare_radius = { default = 0, unit = "m", doc = "second system's particle radius (0: same)" },
  compare_density = { default = 0, unit = "kg/m^3", doc = "second system's density (0: same)" },
  compare_chamber_radius = { default = 0, unit = "m", doc = "second system's chamber radius (0: same)" },
  compare_k_load = { default = 0, unit = "N/m", doc = "second system's stiffness (0: same)" },
}

local function optional(value) if value == 0 then return nil end return value end

local system = {
  particle_count = p.particles,
  particle_radius_m = p.radius,
  particle_density_kg_m3 = p.density,
  chamber_radius_m = p.chamber_radius,
  inner_piece_radius_m = p.inner_radius,
  gap_m = p.gap,
  rotation_speed_rpm = p.rpm,
  restitution = p.restitution,
  stiffness_n_m = optional(p.k_load),
  young_modulus_pa = optional(p.young),
  depth_m = optional(p.depth),
  steps_per_contact = p.steps_per_contact,
  safety_factor = p.safety_factor,
  max_deformation_fraction = p.max_deformation,
  impact_velocity_m_s = optional(p.impact_velocity),
}

local report = kinetic.scaling(system)
print(kinetic.format_report(report))
-- One machine-readable line for scripts and tests.
print(string.format("k_bound_gap_transit=%.4g k_bound_collision_time=%.4g k_min=%.4g k_max=%s dt_at_k_min=%.4g "
  .. "solid_fraction=%.4f G=%.4f J=%.4f", report.k_bound_gap_transit_n_m, report.k_bound_collision_time_n_m,
  report.k_recommended_min_n_m, report.k_recommended_max_n_m and string.format("%.4g", report.k_recommended_max_n_m) or "none",
  report.time_step_at_min_s, report.solid_fraction, report.g_factor, report.j_factor))

local compared = false
local other = {}
for k, v in pairs(system) do other[k] = v end
for parameter, field in pairs { compare_rpm = "rotation_speed_rpm", compare_gap = "gap_m",
                                compare_radius = "particle_radius_m", compare_density = "particle_density_kg_m3",
                                compare_chamber_radius = "chamber_radius_m", compare_k_load = "stiffness_n_m" } do
  if p[parameter] ~= 0 then other[field], compared = p[parameter], true end
end
if compared then
  if system.stiffness_n_m == nil or other.stiffness_n_m == nil then
    error("the similarity ratio (Eq. 5.11) needs k_load for both systems")
  end
  local ratio = kinetic.similarity_ratio(system, other)
  print(string.format("similarity ratio F_this / F_other (Eq. 5.11) = %.6g", ratio))
end
