-- granule.kinetic against dissertation chapter 5: Table 5.1, the stiffness
-- bounds of 5.4.2, the relations between 5.3-5.6 and 5.12-5.15, the
-- similarity ratio 5.11 and the time step 4.1. Every assertion can fail.
local H = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/helpers.lua")
local kinetic = require "granule.kinetic"
local granule = require "granule"

local pi = math.pi

-- Table 5.1 for the base case of Table 4.1 (nu from the annulus area times one
-- diameter, SPEC 5). Tolerance: half a unit in the last digit the table prints.
local base = kinetic.base_case()
local report = kinetic.scaling(base)
H.near(report.solid_fraction, 0.3048, 0.5e-4, "Table 5.1 solid fraction nu")
H.near(report.g_factor, 0.7687, 0.5e-4, "Table 5.1 G")
H.near(report.j_factor, 1.8606, 0.5e-4, "Table 5.1 J")

-- nu by hand: 1500 spheres of 0.4 mm in the annulus 12.5 mm / 5 mm, 0.4 mm deep.
local by_hand = 1500 * (pi * 0.4e-3 ^ 3 / 6) / (pi * (12.5e-3 ^ 2 - 5e-3 ^ 2) * 0.4e-3)
H.relative(report.solid_fraction, by_hand, 1e-12, "solid fraction = N pi d^3/6 / (annulus x d)")
-- A slab depth replaces the diameter: 4 diameters deep holds 4x the particles at the same nu (app. A).
H.relative(kinetic.solid_fraction { particle_count = 6000, particle_radius_m = 0.2e-3, chamber_radius_m = 12.5e-3,
  inner_piece_radius_m = 5e-3, depth_m = 1.6e-3 }, by_hand, 1e-12, "3D slab of 4 diameters, 6000 particles")

-- G = nu g0 with g0 in its three-term form (chapter 5), not only the closed form.
for _, nu in ipairs { 0.05, 0.3048, 0.5, 0.6 } do
  local g0 = 1 / (1 - nu) + 3 * nu / (2 * (1 - nu) ^ 2) + nu ^ 2 / (2 * (1 - nu) ^ 3)
  H.relative(kinetic.radial_distribution(nu), g0, 1e-12, "g0 closed form at nu = " .. nu)
  H.relative(kinetic.g_factor(nu), nu * g0, 1e-12, "G = nu g0 at nu = " .. nu)
end
-- J as Eq. 5.3 writes it; Table 5.1's printed (1 + pi/12)(...)^2 would give 4.15 for G = 0.7687.
H.check(math.abs((1 + pi / 12) * (1 + 5 / (8 * 0.7687)) ^ 2 - 1.8606) > 0.1,
  "the misprinted form of Table 5.1 must not reproduce 1.8606 (else the typo note is wrong)")

-- The two K bounds of 5.4.2: 4000 rpm, H = 1.6 mm: K >> 1.7 N/m (5.12) and K >> 157.8 N/m (5.15).
local fast = kinetic.scaling(kinetic.base_case { rotation_speed_rpm = 4000, gap_m = 1.6e-3 })
H.near(fast.k_bound_gap_transit_n_m, 1.7, 0.05, "Eq. 5.12 bound at 4000 rpm")
H.near(fast.k_bound_collision_time_n_m, 157.8, 0.05, "Eq. 5.15 bound at 4000 rpm")

-- 5.12 and 5.15 are tau_c = tau_f and tau_c = tau_t solved for K: at the bound
-- (with the exact coefficient 48^2/(15 pi) for 5.15) the times are equal.
local s = kinetic.system(kinetic.base_case { rotation_speed_rpm = 4000 })
local flow = { particle_mass_kg = s.particle_mass_kg, angular_velocity_rad_s = s.angular_velocity_rad_s,
               chamber_radius_m = s.chamber_radius_m, gap_m = s.gap_m }
local k_transit = kinetic.stiffness_bound_gap_transit(flow)
H.relative(kinetic.contact_time { particle_mass_kg = s.particle_mass_kg, stiffness_n_m = k_transit },
  s.gap_m / (s.angular_velocity_rad_s * s.chamber_radius_m), 1e-12, "tau_c = tau_f at the 5.12 bound")
local k_collision = kinetic.stiffness_bound_collision_time { particle_mass_kg = s.particle_mass_kg,
  angular_velocity_rad_s = s.angular_velocity_rad_s, chamber_radius_m = s.chamber_radius_m, gap_m = s.gap_m,
  solid_fraction = fast.solid_fraction, restitution = s.restitution,
  coefficient = kinetic.COLLISION_TIME_COEFFICIENT_EXACT }
H.relative(kinetic.contact_time { particle_mass_kg = s.particle_mass_kg, stiffness_n_m = k_collision },
  fast.mean_free_time_s, 1e-12, "tau_c = tau_t (5.13) at the exact 5.15 bound")
-- 5.14 is 5.13 with T from 5.4 and 5.6: d cancels.
local tau_514 = 1 / (24 * fast.g_factor / math.sqrt(pi) * math.sqrt(fast.j_factor / (15 * (1 - s.restitution)))
                     * s.angular_velocity_rad_s * s.chamber_radius_m / s.gap_m)
H.relative(fast.mean_free_time_s, tau_514, 1e-12, "Eq. 5.13 = Eq. 5.14")

-- Simple shear (5.3-5.5): stresses and T go as the square of the shear rate;
-- 5.5's normal stress is 5.3 with T of 5.4; 5.2's pressure tends to 5.3's as e -> 1.
local shear_args = { solid_fraction = 0.3, restitution = 0.85, particle_density_kg_m3 = 1200,
                     particle_diameter_m = 0.4e-3, shear_rate_1_s = 1000 }
local one = kinetic.simple_shear(shear_args)
shear_args.shear_rate_1_s = 3000
local three = kinetic.simple_shear(shear_args)
H.relative(three.normal_stress_pa / one.normal_stress_pa, 9, 1e-12, "sigma_yy ~ (du/dy)^2 (5.5)")
H.relative(three.shear_stress_pa / one.shear_stress_pa, 9, 1e-12, "sigma_xy ~ (du/dy)^2 (5.5)")
H.relative(three.granular_temperature_m2_s2 / one.granular_temperature_m2_s2, 9, 1e-12, "T ~ (du/dy)^2 (5.4)")
local g, j = kinetic.g_factor(0.3), kinetic.j_factor(kinetic.g_factor(0.3))
H.relative(one.normal_stress_pa, 0.3 * (1 + 4 * g) * j / (15 * 0.15) * 1200 * 0.4e-3 ^ 2 * 1000 ^ 2, 1e-12,
  "sigma_yy of Eq. 5.5")
H.relative(one.shear_stress_pa, 8 * j / (5 * math.sqrt(pi)) * math.sqrt(j / (15 * 0.15)) * 0.3 * g * 0.4e-3 ^ 2
  * 1200 * 1000 ^ 2, 1e-12, "sigma_xy of Eq. 5.5 with the sqrt(pi) of Eq. 5.3")
local nearly_elastic = kinetic.simple_shear { solid_fraction = 0.3, restitution = 0.999999,
  particle_density_kg_m3 = 1200, particle_diameter_m = 0.4e-3, shear_rate_1_s = 1000 }
H.relative(nearly_elastic.pressure_pa, nearly_elastic.normal_stress_pa, 1e-5, "5.2 pressure -> 5.3 as e -> 1")

-- Similarity ratio (5.11): 1 for identical systems; each factor as the formula says.
local reference = kinetic.base_case()
H.relative(kinetic.similarity_ratio(reference, kinetic.base_case()), 1, 1e-12, "identical systems")
local function ratio_with(overrides) return kinetic.similarity_ratio(kinetic.base_case(overrides), reference) end
H.relative(ratio_with { rotation_speed_rpm = 4000 }, 2, 1e-12, "F ~ omega")
H.relative(ratio_with { gap_m = 3.2e-3 }, 0.5, 1e-12, "F ~ 1/H")
H.relative(ratio_with { stiffness_n_m = 80000 }, 2, 1e-12, "F ~ K^(1/2)")
H.relative(ratio_with { particle_density_kg_m3 = 4800 }, 2, 1e-12, "F ~ m^(1/2)")
H.relative(ratio_with { chamber_radius_m = 37.5e-3 }, 3, 1e-12, "F ~ R")
H.relative(ratio_with { particle_radius_m = 0.4e-3 }, 2 * math.sqrt(8), 1e-12, "F ~ d m^(1/2) ~ d^(5/2)")
-- The double-sized system of 5.3.2 (all lengths x2, same particles and speed): same force.
H.relative(ratio_with { chamber_radius_m = 25e-3, inner_piece_radius_m = 10e-3, gap_m = 3.2e-3,
  particle_count = 6000 }, 1, 1e-12, "double-sized system of 5.3.2")
-- The two speed units agree.
H.relative(kinetic.similarity_ratio(kinetic.base_case { angular_velocity_rad_s = granule.rpm(2000) }, reference),
  1, 1e-12, "rad/s and rpm")

-- Time step (4.1), the engine's helper and the engine itself agree.
local m = kinetic.particle_mass(0.2e-3, 1200)
local dt = kinetic.time_step { particle_mass_kg = m, stiffness_n_m = 20000, restitution = 0.85 }
H.relative(dt, pi * 0.85 * math.sqrt(m / 40000) / 40, 1e-12, "Eq. 4.1")
H.relative(dt, granule.walton_braun_time_step(m, 20000, 0.85, 40), 1e-12, "granule.walton_braun_time_step")
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:contact { "powder", "powder", model = "walton_braun", k_load = 20000, restitution = 0.85, friction = 0.4 }
sim:add_particle { position = { 0, 0 }, radius = 0.2e-3, material = "powder" }
sim:add_particle { position = { 1e-3, 0 }, radius = 0.2e-3, material = "powder" }
H.relative(sim:time_step(), dt, 1e-9, "the engine's automatic time step (Eq. 4.1)")

-- The recommended range: above every bound by the safety factor, the scene's
-- K = 20000 N/m of Table 4.1 inside it, a larger K giving a smaller step.
H.check(report.k_recommended_min_n_m >= 10 * report.k_bound_collision_time_n_m, "lowest K >= 10 x bound 5.15")
H.check(report.k_recommended_min_n_m >= 10 * report.k_bound_gap_transit_n_m, "lowest K >= 10 x bound 5.12")
H.check(report.k_recommended_min_n_m >= report.k_bound_deformation_n_m, "lowest K >= deformation bound")
H.relative(report.k_recommended_max_n_m, 0.01 * pi * 3.3e9 * 0.2e-3, 1e-12, "highest K from Eq. 4.2")
H.check(report.stiffness_ok, "Table 4.1's K = 20000 N/m lies in the recommended range")
H.check(report.time_step_at_min_s > report.time_step_at_max_s, "the softer end allows the larger step")
-- At the deformation bound the head-on overlap at the impact speed is exactly 1 % of d.
local k_def = report.k_bound_deformation_n_m
H.relative(report.impact_velocity_m_s * math.sqrt(m / (2 * k_def)), 0.01 * 0.4e-3, 1e-12,
  "overlap at the deformation bound")

-- Bad input is refused with the parameter's name.
H.fails("particle_radius_m", kinetic.scaling, kinetic.base_case { particle_radius_m = -1 })
H.fails("gap_m", kinetic.scaling, kinetic.base_case { gap_m = 0 / 0 })
H.fails("restitution", kinetic.scaling, kinetic.base_case { restitution = 1 })
H.fails("did you mean 'gap_m'", kinetic.system, { gap = 1.6e-3 })
H.fails("solid_fraction", kinetic.g_factor, 1.2)
H.fails("inner_piece_radius_m", kinetic.solid_fraction, { particle_count = 10, particle_radius_m = 1e-3,
  chamber_radius_m = 1e-2, inner_piece_radius_m = 2e-2 })
H.fails("stiffness_n_m", kinetic.similarity_ratio, kinetic.base_case(), kinetic.base_case { stiffness_n_m = -5 })
H.fails("too many particles", kinetic.scaling, kinetic.base_case { particle_count = 1e5 })

print("analysis.kinetic ok")
