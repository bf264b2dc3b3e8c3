-- granule.kinetic: the kinetic-theory scaling of dissertation chapter 5, as
-- plain functions: solid fraction, G and J (Table 5.1), granular temperature
-- and stresses of simple shear (5.2-5.5), the stiffness constraints (5.12,
-- 5.15), the similarity ratio between two systems (5.11), and a recommended
-- stiffness range with the time step (Eq. 4.1) it implies.
--
--   local kinetic = require "granule.kinetic"
--   local report = kinetic.scaling(kinetic.base_case { rotation_speed_rpm = 4000 })
--   print(kinetic.format_report(report))
--
-- A "system" is a table describing a Mechanofusion scene (SI units, names
-- carry the unit); kinetic.system() checks it and fills the defaults:
--   particle_radius_m, particle_density_kg_m3, particle_count,
--   chamber_radius_m, inner_piece_radius_m, gap_m,
--   rotation_speed_rpm or angular_velocity_rad_s,
--   restitution                       e of the collisions, in (0, 1)
--   depth_m                           slab depth of the volume; default one
--                                     particle diameter (2D, SPEC 5)
--   stiffness_n_m                     optional: the K a scene uses
--   young_modulus_pa                  optional: gives Eq. 4.2's K = 0.01 pi E r
--   steps_per_contact                 n of Eq. 4.1, default 40
--   safety_factor                     how much larger ">>" means, default 10
--   max_deformation_fraction          overlap / diameter allowed, default 0.01
--   impact_velocity_m_s               optional: the impact speed for the
--                                     deformation limit (default: kinetic estimate)
local checks = require "granule.checks"

local M = {}

local pi = math.pi

--- kinetic.COLLISION_TIME_COEFFICIENT = 50, the rounded coefficient Eq. 5.15 prints.
M.COLLISION_TIME_COEFFICIENT = 50
--- kinetic.COLLISION_TIME_COEFFICIENT_EXACT = 48^2 / (15 pi) = 48.89: what squaring
--- the inequality before 5.15 gives; 5.4.2's 157.8 N/m uses the rounded 50.
M.COLLISION_TIME_COEFFICIENT_EXACT = 48 ^ 2 / (15 * pi)

local function keyword_args(where, args, keys)
  checks.table_arg(where, args, table.concat(keys, ", "))
  checks.known_keys(where, args, keys)
  return args
end

local function restitution_arg(where, e)
  -- e = 1 makes the dissipation of 5.4 vanish (T unbounded); e = 0 is no bounce.
  return checks.open_interval(where, "restitution", e, 0, 1)
end

local function solid_fraction_arg(where, nu)
  return checks.open_interval(where, "solid_fraction", nu, 0, 1)
end

--- kinetic.particle_mass(particle_radius_m, particle_density_kg_m3) -> m = (4/3) pi r^3 rho [kg]
--- (particles are spheres in 2D too, SPEC 2).
function M.particle_mass(particle_radius_m, particle_density_kg_m3)
  local where = "kinetic.particle_mass"
  checks.positive(where, "particle_radius_m", particle_radius_m, "m")
  checks.positive(where, "particle_density_kg_m3", particle_density_kg_m3, "kg/m^3")
  return 4 / 3 * pi * particle_radius_m ^ 3 * particle_density_kg_m3
end

--- kinetic.solid_fraction { particle_count, particle_radius_m, chamber_radius_m,
---                          inner_piece_radius_m, [depth_m = 2 r] } -> nu
--- nu = n pi d^3 / 6 (5.2, Table 5.1) with n = N / V, V the annulus between the
--- chamber wall and the inner piece times depth_m: one particle diameter for the
--- 2D system (SPEC 5), the slab length in 3D. Table 4.1 gives 0.3048.
function M.solid_fraction(args)
  local where = "kinetic.solid_fraction"
  keyword_args(where, args, { "particle_count", "particle_radius_m", "chamber_radius_m",
                              "inner_piece_radius_m", "depth_m" })
  local count = checks.positive(where, "particle_count", args.particle_count, "-")
  local r = checks.positive(where, "particle_radius_m", args.particle_radius_m, "m")
  local r_chamber = checks.positive(where, "chamber_radius_m", args.chamber_radius_m, "m")
  local r_inner = checks.non_negative(where, "inner_piece_radius_m", args.inner_piece_radius_m, "m")
  if r_inner >= r_chamber then
    checks.fail(where, "inner_piece_radius_m", string.format("< chamber_radius_m = %g m", r_chamber), r_inner)
  end
  local depth = args.depth_m == nil and 2 * r or checks.positive(where, "depth_m", args.depth_m, "m")
  local volume = pi * (r_chamber ^ 2 - r_inner ^ 2) * depth
  local d = 2 * r
  return count * pi * d ^ 3 / 6 / volume
end

--- kinetic.radial_distribution(solid_fraction) -> g0(nu) (chapter 5, with G):
--- g0 = 1/(1 - nu) + 3 nu / (2 (1 - nu)^2) + nu^2 / (2 (1 - nu)^3)
---    = (2 - nu) / (2 (1 - nu)^3)   (Carnahan-Starling value at contact).
function M.radial_distribution(solid_fraction)
  local nu = solid_fraction_arg("kinetic.radial_distribution", solid_fraction)
  return (2 - nu) / (2 * (1 - nu) ^ 3)
end

--- kinetic.g_factor(solid_fraction) -> G = nu g0(nu) = nu (2 - nu) / (2 (1 - nu)^3)
--- (chapter 5; Table 5.1 gives 0.7687 for nu = 0.3048).
function M.g_factor(solid_fraction)
  local nu = solid_fraction_arg("kinetic.g_factor", solid_fraction)
  return nu * (2 - nu) / (2 * (1 - nu) ^ 3)
end

--- kinetic.j_factor(g_factor) -> J = 1 + (pi/12) (1 + 5 / (8 G))^2 (Eq. 5.3).
--- Table 5.1 prints (1 + pi/12)(1 + 5/(8G))^2, a typo: its own value 1.8606
--- for G = 0.7687 is what the form of Eq. 5.3 gives (SPEC 5).
function M.j_factor(g_factor)
  local g = checks.positive("kinetic.j_factor", "g_factor", g_factor, "-")
  return 1 + pi / 12 * (1 + 5 / (8 * g)) ^ 2
end

--- kinetic.shear_rate { angular_velocity_rad_s, chamber_radius_m, gap_m } -> du/dy = omega R / H [1/s]
--- (Eq. 5.6: the chamber wall moves at omega R across the gap H to the inner piece).
function M.shear_rate(args)
  local where = "kinetic.shear_rate"
  keyword_args(where, args, { "angular_velocity_rad_s", "chamber_radius_m", "gap_m" })
  local omega = checks.positive(where, "angular_velocity_rad_s", args.angular_velocity_rad_s, "rad/s")
  local r = checks.positive(where, "chamber_radius_m", args.chamber_radius_m, "m")
  local h = checks.positive(where, "gap_m", args.gap_m, "m")
  return omega * r / h
end

--- kinetic.granular_temperature { solid_fraction, restitution, particle_diameter_m, shear_rate_1_s }
--- -> T [m^2/s^2], Eq. 5.4: T^(1/2) = (J / (15 (1 - e)))^(1/2) d du/dy,
--- the balance of shear production and inelastic dissipation in simple shear.
function M.granular_temperature(args)
  local where = "kinetic.granular_temperature"
  keyword_args(where, args, { "solid_fraction", "restitution", "particle_diameter_m", "shear_rate_1_s" })
  local nu = solid_fraction_arg(where, args.solid_fraction)
  local e = restitution_arg(where, args.restitution)
  local d = checks.positive(where, "particle_diameter_m", args.particle_diameter_m, "m")
  local shear = checks.non_negative(where, "shear_rate_1_s", args.shear_rate_1_s, "1/s")
  local j = M.j_factor(M.g_factor(nu))
  return j / (15 * (1 - e)) * d ^ 2 * shear ^ 2
end

--- kinetic.simple_shear { solid_fraction, restitution, particle_density_kg_m3, particle_diameter_m,
---                        shear_rate_1_s } -> table:
---   g_factor, j_factor                G, J
---   granular_temperature_m2_s2        T, Eq. 5.4
---   pressure_pa                       p = nu rho (1 + 2 G (1 + e)) T      (5.1-5.2, any e)
---   normal_stress_pa                  sigma_yy = nu rho (1 + 4 G) T       (5.3, e ~ 1; = 5.5)
---   shear_stress_pa                   sigma_xy = 8 J / (5 sqrt(pi)) nu G d rho T^(1/2) du/dy (5.3)
---   mean_free_time_s                  tau_t = d / ((24 G / sqrt(pi)) T^(1/2))  (5.13)
--- Eq. 5.5 prints sigma_xy = (8 J / 5) (J / (15 (1 - e)))^(1/2) nu G d^2 rho (du/dy)^2
--- without the sqrt(pi) of 5.3; substituting 5.4 into 5.3 keeps it, so we do.
function M.simple_shear(args)
  local where = "kinetic.simple_shear"
  keyword_args(where, args, { "solid_fraction", "restitution", "particle_density_kg_m3",
                              "particle_diameter_m", "shear_rate_1_s" })
  local nu = solid_fraction_arg(where, args.solid_fraction)
  local e = restitution_arg(where, args.restitution)
  local rho = checks.positive(where, "particle_density_kg_m3", args.particle_density_kg_m3, "kg/m^3")
  local d = checks.positive(where, "particle_diameter_m", args.particle_diameter_m, "m")
  local shear = checks.non_negative(where, "shear_rate_1_s", args.shear_rate_1_s, "1/s")
  local g = M.g_factor(nu)
  local j = M.j_factor(g)
  local t = M.granular_temperature { solid_fraction = nu, restitution = e, particle_diameter_m = d,
                                     shear_rate_1_s = shear }
  local out = {
    solid_fraction = nu,
    g_factor = g,
    j_factor = j,
    granular_temperature_m2_s2 = t,
    pressure_pa = nu * rho * (1 + 2 * g * (1 + e)) * t,
    normal_stress_pa = nu * rho * (1 + 4 * g) * t,
    shear_stress_pa = 8 * j / (5 * math.sqrt(pi)) * nu * g * d * rho * math.sqrt(t) * shear,
  }
  out.mean_free_time_s = t > 0 and d / (24 * g / math.sqrt(pi) * math.sqrt(t)) or math.huge
  return out
end

--- kinetic.contact_time { particle_mass_kg, stiffness_n_m } -> tau_c = 2 (m / K)^(1/2) [s] (5.4.1).
function M.contact_time(args)
  local where = "kinetic.contact_time"
  keyword_args(where, args, { "particle_mass_kg", "stiffness_n_m" })
  local m = checks.positive(where, "particle_mass_kg", args.particle_mass_kg, "kg")
  local k = checks.positive(where, "stiffness_n_m", args.stiffness_n_m, "N/m")
  return 2 * math.sqrt(m / k)
end

local flow_keys = { "particle_mass_kg", "angular_velocity_rad_s", "chamber_radius_m", "gap_m" }
local function flow_args(where, args, extra)
  local keys = { table.unpack(flow_keys) }
  for _, k in ipairs(extra or {}) do keys[#keys + 1] = k end
  keyword_args(where, args, keys)
  return checks.positive(where, "particle_mass_kg", args.particle_mass_kg, "kg"),
         checks.positive(where, "angular_velocity_rad_s", args.angular_velocity_rad_s, "rad/s"),
         checks.positive(where, "chamber_radius_m", args.chamber_radius_m, "m"),
         checks.positive(where, "gap_m", args.gap_m, "m")
end

--- kinetic.stiffness_bound_gap_transit { particle_mass_kg, angular_velocity_rad_s, chamber_radius_m, gap_m }
--- -> K [N/m] of Eq. 5.12: K >> m (2 omega R / H)^2, i.e. the contact time
--- tau_c = 2 (m/K)^(1/2) is much shorter than the time tau_f = H / (omega R)
--- to cross the gap. 1.7 N/m at 4000 rpm, H = 1.6 mm (5.4.2).
function M.stiffness_bound_gap_transit(args)
  local m, omega, r, h = flow_args("kinetic.stiffness_bound_gap_transit", args)
  return m * (2 * omega * r / h) ^ 2
end

--- kinetic.stiffness_bound_collision_time { particle_mass_kg, angular_velocity_rad_s, chamber_radius_m,
---                                          gap_m, solid_fraction, restitution, [coefficient = 50] }
--- -> K [N/m] of Eq. 5.15: K >> c J G^2 / (1 - e) (R / H)^2 m omega^2, i.e. the
--- contact time is much shorter than the time between collisions (5.13-5.14).
--- c = 50 as printed (157.8 N/m at 4000 rpm, H = 1.6 mm); the derivation gives
--- 48^2 / (15 pi) = 48.89 (kinetic.COLLISION_TIME_COEFFICIENT_EXACT).
function M.stiffness_bound_collision_time(args)
  local where = "kinetic.stiffness_bound_collision_time"
  local m, omega, r, h = flow_args(where, args, { "solid_fraction", "restitution", "coefficient" })
  local nu = solid_fraction_arg(where, args.solid_fraction)
  local e = restitution_arg(where, args.restitution)
  local c = args.coefficient == nil and M.COLLISION_TIME_COEFFICIENT
            or checks.positive(where, "coefficient", args.coefficient, "-")
  local g = M.g_factor(nu)
  local j = M.j_factor(g)
  return c * j * g ^ 2 / (1 - e) * (r / h) ^ 2 * m * omega ^ 2
end

--- kinetic.stiffness_bound_deformation { particle_mass_kg, particle_diameter_m, impact_velocity_m_s,
---                                       [max_deformation_fraction = 0.01] } -> K [N/m]
--- The third condition of 5.4.1 (and of Eq. 4.2): the largest overlap stays
--- below max_deformation_fraction d. Two equal spheres meeting head-on at v
--- with a linear loading spring reach delta = v (m / (2 K))^(1/2), so
--- K >= (m / 2) (v / (f d))^2.
function M.stiffness_bound_deformation(args)
  local where = "kinetic.stiffness_bound_deformation"
  keyword_args(where, args, { "particle_mass_kg", "particle_diameter_m", "impact_velocity_m_s",
                              "max_deformation_fraction" })
  local m = checks.positive(where, "particle_mass_kg", args.particle_mass_kg, "kg")
  local d = checks.positive(where, "particle_diameter_m", args.particle_diameter_m, "m")
  local v = checks.non_negative(where, "impact_velocity_m_s", args.impact_velocity_m_s, "m/s")
  local f = args.max_deformation_fraction == nil and 0.01
            or checks.half_open(where, "max_deformation_fraction", args.max_deformation_fraction, 0, 1)
  return m / 2 * (v / (f * d)) ^ 2
end

--- kinetic.time_step { particle_mass_kg, stiffness_n_m, restitution, [steps_per_contact = 40] }
--- -> dt [s], Eq. 4.1: dt = pi e (m / (2 K))^(1/2) / n.
function M.time_step(args)
  local where = "kinetic.time_step"
  keyword_args(where, args, { "particle_mass_kg", "stiffness_n_m", "restitution", "steps_per_contact" })
  local m = checks.positive(where, "particle_mass_kg", args.particle_mass_kg, "kg")
  local k = checks.positive(where, "stiffness_n_m", args.stiffness_n_m, "N/m")
  local e = checks.half_open(where, "restitution", args.restitution, 0, 1)
  local n = args.steps_per_contact == nil and 40 or checks.positive(where, "steps_per_contact", args.steps_per_contact, "-")
  return pi * e * math.sqrt(m / (2 * k)) / n
end

-- ---------------------------------------------------------------------------
-- Systems: a scene's parameters in one table.

local system_keys = {
  "particle_radius_m", "particle_density_kg_m3", "particle_count", "chamber_radius_m",
  "inner_piece_radius_m", "gap_m", "rotation_speed_rpm", "angular_velocity_rad_s", "restitution",
  "depth_m", "stiffness_n_m", "young_modulus_pa", "steps_per_contact", "safety_factor",
  "max_deformation_fraction", "impact_velocity_m_s",
}

--- kinetic.base_case([overrides]) -> the system of Table 4.1 (radius 0.2 mm,
--- 1200 kg/m^3, 1500 particles, chamber 25 mm and inner piece 10 mm in
--- diameter, gap 1.6 mm, 2000 rpm, K = 20000 N/m, e = 0.85), with PMMA's
--- E = 3.3 GPa (Table 4.2) for Eq. 4.2; `overrides` replaces any field.
function M.base_case(overrides)
  local system = {
    particle_radius_m = 0.2e-3,
    particle_density_kg_m3 = 1200,
    particle_count = 1500,
    chamber_radius_m = 12.5e-3,
    inner_piece_radius_m = 5e-3,
    gap_m = 1.6e-3,
    rotation_speed_rpm = 2000,
    restitution = 0.85,
    stiffness_n_m = 20000,
    young_modulus_pa = 3.3e9,
    steps_per_contact = 40,
  }
  if overrides ~= nil then
    keyword_args("kinetic.base_case", overrides, system_keys)
    for k, v in pairs(overrides) do system[k] = v end
    -- one speed only: an override in either unit replaces the other
    if overrides.angular_velocity_rad_s ~= nil and overrides.rotation_speed_rpm == nil then
      system.rotation_speed_rpm = nil
    end
  end
  return system
end

--- kinetic.system(t) -> a checked copy of the system table t with the defaults
--- filled and the derived quantities added: particle_diameter_m,
--- particle_mass_kg, angular_velocity_rad_s (from rotation_speed_rpm when only
--- that is given), rotation_speed_rpm, depth_m. Errors name the bad field.
function M.system(t)
  local where = "kinetic.system"
  keyword_args(where, t, system_keys)
  local s = {}
  for k, v in pairs(t) do s[k] = v end
  checks.positive(where, "particle_radius_m", s.particle_radius_m, "m")
  checks.positive(where, "particle_density_kg_m3", s.particle_density_kg_m3, "kg/m^3")
  checks.positive(where, "chamber_radius_m", s.chamber_radius_m, "m")
  checks.positive(where, "gap_m", s.gap_m, "m")
  if s.angular_velocity_rad_s == nil and s.rotation_speed_rpm == nil then
    checks.raise(where .. ": give 'rotation_speed_rpm' (1/min) or 'angular_velocity_rad_s' (rad/s)")
  end
  if s.angular_velocity_rad_s ~= nil then
    checks.positive(where, "angular_velocity_rad_s", s.angular_velocity_rad_s, "rad/s")
    if s.rotation_speed_rpm ~= nil then
      checks.positive(where, "rotation_speed_rpm", s.rotation_speed_rpm, "1/min")
      local from_rpm = s.rotation_speed_rpm * 2 * pi / 60
      if math.abs(from_rpm - s.angular_velocity_rad_s) > 1e-9 * from_rpm then
        checks.raise(string.format("%s: rotation_speed_rpm = %g and angular_velocity_rad_s = %g disagree; give one",
          where, s.rotation_speed_rpm, s.angular_velocity_rad_s))
      end
    end
    s.rotation_speed_rpm = s.angular_velocity_rad_s * 60 / (2 * pi)
  else
    checks.positive(where, "rotation_speed_rpm", s.rotation_speed_rpm, "1/min")
    s.angular_velocity_rad_s = s.rotation_speed_rpm * 2 * pi / 60
  end
  restitution_arg(where, s.restitution)
  s.particle_diameter_m = 2 * s.particle_radius_m
  s.particle_mass_kg = M.particle_mass(s.particle_radius_m, s.particle_density_kg_m3)
  s.depth_m = s.depth_m == nil and s.particle_diameter_m or checks.positive(where, "depth_m", s.depth_m, "m")
  if s.particle_count ~= nil then checks.positive(where, "particle_count", s.particle_count, "-") end
  if s.inner_piece_radius_m ~= nil then checks.non_negative(where, "inner_piece_radius_m", s.inner_piece_radius_m, "m") end
  if s.stiffness_n_m ~= nil then checks.positive(where, "stiffness_n_m", s.stiffness_n_m, "N/m") end
  if s.young_modulus_pa ~= nil then checks.positive(where, "young_modulus_pa", s.young_modulus_pa, "Pa") end
  s.steps_per_contact = s.steps_per_contact == nil and 40 or checks.positive(where, "steps_per_contact", s.steps_per_contact, "-")
  s.safety_factor = s.safety_factor == nil and 10 or checks.positive(where, "safety_factor", s.safety_factor, "-")
  s.max_deformation_fraction = s.max_deformation_fraction == nil and 0.01
    or checks.half_open(where, "max_deformation_fraction", s.max_deformation_fraction, 0, 1)
  if s.impact_velocity_m_s ~= nil then checks.positive(where, "impact_velocity_m_s", s.impact_velocity_m_s, "m/s") end
  return s
end

--- kinetic.mean_force_scale(system) -> (d / H) omega R (m K)^(1/2) [N], Eq. 5.10:
--- the average collision force in the gap up to a constant factor (it needs
--- particle_radius_m, particle_density_kg_m3, gap_m, chamber_radius_m, the
--- speed and stiffness_n_m).
function M.mean_force_scale(system)
  local s = M.system(system)
  if s.stiffness_n_m == nil then checks.raise("kinetic.mean_force_scale: the system needs 'stiffness_n_m' (Eq. 5.10)") end
  return s.particle_diameter_m / s.gap_m * s.angular_velocity_rad_s * s.chamber_radius_m
         * math.sqrt(s.particle_mass_kg * s.stiffness_n_m)
end

--- kinetic.similarity_ratio(simulated, real) -> F_s / F_r, Eq. 5.11:
--- (d_s / H_s) omega_s R_s (m_s K_s)^(1/2) / ((d_r / H_r) omega_r R_r (m_r K_r)^(1/2)).
--- Both are system tables (see kinetic.system) with stiffness_n_m. Multiply a
--- force measured in the real system by it to get the simulated one, or divide
--- a simulated force by it to estimate the real one.
function M.similarity_ratio(simulated, real)
  local where = "kinetic.similarity_ratio"
  checks.table_arg(where, simulated, "the simulated system")
  checks.table_arg(where, real, "the real system")
  return M.mean_force_scale(simulated) / M.mean_force_scale(real)
end

--- kinetic.scaling(system) -> report table with everything chapter 5 says about
--- the system (see kinetic.format_report for a readable table):
---   solid_fraction, g_factor, j_factor               Table 5.1
---   shear_rate_1_s (5.6), granular_temperature_m2_s2 (5.4), normal_stress_pa,
---   shear_stress_pa (5.5), mean_free_time_s (5.13), gap_transit_time_s (tau_f)
---   impact_velocity_m_s   the deformation check's impact speed: the given one,
---                         or the mean relative speed 4 (T / pi)^(1/2) of two
---                         particles whose velocities scatter with variance T
---   k_bound_gap_transit_n_m (5.12), k_bound_collision_time_n_m (5.15),
---   k_bound_deformation_n_m (1 % of d at impact_velocity_m_s)
---   k_recommended_min_n_m = max(safety x 5.12, safety x 5.15, deformation)
---   k_recommended_max_n_m = 0.01 pi E r (Eq. 4.2) when young_modulus_pa is given:
---                         the stiffness of the material itself; stiffer only costs time
---   time_step_at_min_s, time_step_at_max_s (Eq. 4.1)
---   and, when stiffness_n_m is given: stiffness_n_m, contact_time_s, time_step_s,
---   stiffness_ok (K within the recommended range), margins k / bound.
function M.scaling(system)
  local s = M.system(system)
  local where = "kinetic.scaling"
  for _, k in ipairs { "particle_count", "inner_piece_radius_m" } do
    if s[k] == nil then checks.raise(string.format("%s: the system needs '%s' for the solid fraction", where, k)) end
  end
  local r = {}
  r.system = s
  r.solid_fraction = M.solid_fraction { particle_count = s.particle_count, particle_radius_m = s.particle_radius_m,
    chamber_radius_m = s.chamber_radius_m, inner_piece_radius_m = s.inner_piece_radius_m, depth_m = s.depth_m }
  if r.solid_fraction >= 1 then
    checks.raise(string.format("%s: solid fraction %.3g >= 1: too many particles for the annulus", where, r.solid_fraction))
  end
  r.g_factor = M.g_factor(r.solid_fraction)
  r.j_factor = M.j_factor(r.g_factor)
  r.shear_rate_1_s = M.shear_rate { angular_velocity_rad_s = s.angular_velocity_rad_s,
    chamber_radius_m = s.chamber_radius_m, gap_m = s.gap_m }
  local shear = M.simple_shear { solid_fraction = r.solid_fraction, restitution = s.restitution,
    particle_density_kg_m3 = s.particle_density_kg_m3, particle_diameter_m = s.particle_diameter_m,
    shear_rate_1_s = r.shear_rate_1_s }
  r.granular_temperature_m2_s2 = shear.granular_temperature_m2_s2
  r.normal_stress_pa = shear.normal_stress_pa
  r.shear_stress_pa = shear.shear_stress_pa
  r.mean_free_time_s = shear.mean_free_time_s
  r.gap_transit_time_s = s.gap_m / (s.angular_velocity_rad_s * s.chamber_radius_m)
  r.impact_velocity_m_s = s.impact_velocity_m_s or 4 * math.sqrt(r.granular_temperature_m2_s2 / pi)
  r.impact_velocity_estimated = s.impact_velocity_m_s == nil
  local flow = { particle_mass_kg = s.particle_mass_kg, angular_velocity_rad_s = s.angular_velocity_rad_s,
                 chamber_radius_m = s.chamber_radius_m, gap_m = s.gap_m }
  r.k_bound_gap_transit_n_m = M.stiffness_bound_gap_transit(flow)
  flow.solid_fraction, flow.restitution = r.solid_fraction, s.restitution
  r.k_bound_collision_time_n_m = M.stiffness_bound_collision_time(flow)
  r.k_bound_deformation_n_m = M.stiffness_bound_deformation { particle_mass_kg = s.particle_mass_kg,
    particle_diameter_m = s.particle_diameter_m, impact_velocity_m_s = r.impact_velocity_m_s,
    max_deformation_fraction = s.max_deformation_fraction }
  r.k_recommended_min_n_m = math.max(s.safety_factor * r.k_bound_gap_transit_n_m,
    s.safety_factor * r.k_bound_collision_time_n_m, r.k_bound_deformation_n_m)
  if s.young_modulus_pa ~= nil then
    r.k_recommended_max_n_m = 0.01 * pi * s.young_modulus_pa * s.particle_radius_m  -- Eq. 4.2
  end
  r.range_empty = r.k_recommended_max_n_m ~= nil and r.k_recommended_max_n_m < r.k_recommended_min_n_m
  local function dt(k)
    return M.time_step { particle_mass_kg = s.particle_mass_kg, stiffness_n_m = k, restitution = s.restitution,
                         steps_per_contact = s.steps_per_contact }
  end
  r.time_step_at_min_s = dt(r.k_recommended_min_n_m)
  if r.k_recommended_max_n_m then r.time_step_at_max_s = dt(r.k_recommended_max_n_m) end
  if s.stiffness_n_m ~= nil then
    local k = s.stiffness_n_m
    r.stiffness_n_m = k
    r.contact_time_s = M.contact_time { particle_mass_kg = s.particle_mass_kg, stiffness_n_m = k }
    r.time_step_s = dt(k)
    r.margin_gap_transit = k / r.k_bound_gap_transit_n_m
    r.margin_collision_time = k / r.k_bound_collision_time_n_m
    r.margin_deformation = k / r.k_bound_deformation_n_m
    r.stiffness_ok = k >= r.k_recommended_min_n_m and (r.k_recommended_max_n_m == nil or k <= r.k_recommended_max_n_m)
  end
  return r
end

local function row(lines, label, value, unit, source)
  local text
  if type(value) == "number" then text = string.format("%.5g", value) else text = tostring(value) end
  lines[#lines + 1] = string.format("  %-36s %14s %-8s %s", label, text, unit or "", source or "")
end

--- kinetic.format_report(report) -> multi-line text: the report of
--- kinetic.scaling as a table of quantity, value, unit and equation.
function M.format_report(r)
  checks.table_arg("kinetic.format_report", r, "the table kinetic.scaling returns")
  local s = r.system
  local lines = {}
  lines[#lines + 1] = string.format("Kinetic-theory scaling (dissertation ch. 5) for %g particles of r = %g m, "
    .. "rho = %g kg/m^3, at %g rpm, gap %g m", s.particle_count, s.particle_radius_m, s.particle_density_kg_m3,
    s.rotation_speed_rpm, s.gap_m)
  lines[#lines + 1] = string.format("  %-36s %14s %-8s %s", "quantity", "value", "unit", "source")
  row(lines, "particle mass m", s.particle_mass_kg, "kg", "(4/3) pi r^3 rho")
  row(lines, "angular velocity omega", s.angular_velocity_rad_s, "rad/s", "2 pi rpm / 60")
  row(lines, "solid fraction nu", r.solid_fraction, "-", "Table 5.1 (annulus x depth)")
  row(lines, "G", r.g_factor, "-", "Table 5.1, nu(2-nu)/(2(1-nu)^3)")
  row(lines, "J", r.j_factor, "-", "Table 5.1, 1+(pi/12)(1+5/(8G))^2")
  row(lines, "shear rate omega R / H", r.shear_rate_1_s, "1/s", "Eq. 5.6")
  row(lines, "granular temperature T", r.granular_temperature_m2_s2, "m^2/s^2", "Eq. 5.4")
  row(lines, "normal stress sigma_yy", r.normal_stress_pa, "Pa", "Eq. 5.5")
  row(lines, "shear stress sigma_xy", r.shear_stress_pa, "Pa", "Eq. 5.3 with 5.4")
  row(lines, "gap transit time tau_f", r.gap_transit_time_s, "s", "H / (omega R)")
  row(lines, "time between collisions tau_t", r.mean_free_time_s, "s", "Eq. 5.13-5.14")
  row(lines, "impact speed for deformation", r.impact_velocity_m_s, "m/s",
    r.impact_velocity_estimated and "4 (T/pi)^(1/2)" or "given")
  row(lines, "K bound, gap transit", r.k_bound_gap_transit_n_m, "N/m", "Eq. 5.12, K >> m(2 omega R/H)^2")
  row(lines, "K bound, collision time", r.k_bound_collision_time_n_m, "N/m", "Eq. 5.15, K >> 50 J G^2/(1-e) (R/H)^2 m omega^2")
  row(lines, "K bound, deformation", r.k_bound_deformation_n_m, "N/m",
    string.format("overlap < %g d", s.max_deformation_fraction))
  row(lines, "K recommended, lowest", r.k_recommended_min_n_m, "N/m",
    string.format("max(%g x bounds 5.12/5.15, deformation)", s.safety_factor))
  if r.k_recommended_max_n_m then
    row(lines, "K recommended, highest", r.k_recommended_max_n_m, "N/m", "Eq. 4.2, 0.01 pi E r")
  else
    row(lines, "K recommended, highest", "none", "N/m", "Eq. 4.2 needs a Young's modulus")
  end
  row(lines, "time step at lowest K", r.time_step_at_min_s, "s",
    string.format("Eq. 4.1, n = %g", s.steps_per_contact))
  if r.time_step_at_max_s then row(lines, "time step at highest K", r.time_step_at_max_s, "s", "Eq. 4.1") end
  if r.range_empty then
    lines[#lines + 1] = "  WARNING: the recommended range is empty (Eq. 4.2's K is below the lowest K)"
  end
  if r.stiffness_n_m then
    row(lines, "K of the scene", r.stiffness_n_m, "N/m", "")
    row(lines, "contact time tau_c", r.contact_time_s, "s", "2 (m/K)^(1/2)")
    row(lines, "time step at the scene's K", r.time_step_s, "s", "Eq. 4.1")
    row(lines, "K / bound 5.12", r.margin_gap_transit, "-", "")
    row(lines, "K / bound 5.15", r.margin_collision_time, "-", "")
    row(lines, "K / deformation bound", r.margin_deformation, "-", "")
    row(lines, "K within the recommended range", r.stiffness_ok and "yes" or "no", "", "")
  end
  return table.concat(lines, "\n")
end

return M
