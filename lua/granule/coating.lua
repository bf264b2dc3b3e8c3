-- granule.coating: the deformation and coating-time estimates of dissertation
-- sections 4.6-4.7 and appendix B, as plain functions.
--
--   local coating = require "granule.coating"
--   local d = coating.guest_deformation { host = "PMMA", guest = "Al2O3", host_radius_m = 200e-6,
--                                         guest_radius_m = 2.5e-6, impact_velocity_m_s = 1 }
--   d.jkr_central_displacement_ratio   --> central displacement / guest diameter
--
-- The chain of appendix B: two host particles meet at the relative velocity v;
-- beyond the limiting elastic velocity (B.1) the Rogers-Reed elastic-plastic
-- impact (B.2-B.5) gives the largest contact radius a_m and the total force P;
-- P is shared by the guest particles inside pi a_m^2 (B.6); each guest is
-- pressed into the host by that force, elastically (Hertz, B.7) or with
-- adhesion (JKR, B.8-B.10). Materials are names from granule.materials or
-- material tables with the same fields. SI units throughout.
local checks = require "granule.checks"
local materials = require "granule.materials"

local M = {}

local pi = math.pi

--- coating.DEFAULT_PACKING_RATIO = 0.79: area fraction of the host surface that
--- the guests cover, "approximately 0.79 under dense packing" (after Eq. B.6).
M.DEFAULT_PACKING_RATIO = 0.79

local function material_arg(where, name, value)
  if value == nil then checks.fail(where, name, "a material name or table", value) end
  return materials.get(value, string.format("%s: '%s'", where, name))
end

--- coating.elastic_constant(material_a, material_b) -> K [Pa], Eq. B.3:
--- K = 4 / (3 pi (k1 + k2)), k_i = (1 - nu_i^2) / (pi E_i).
--- For one material K = (2/3) E / (1 - nu^2); K = (4/3) E* in the usual notation.
function M.elastic_constant(material_a, material_b)
  local where = "coating.elastic_constant"
  local a = material_arg(where, "material_a", material_a)
  local b = material_arg(where, "material_b", material_b == nil and material_a or material_b)
  local k_a = (1 - a.poisson_ratio ^ 2) / (pi * a.young_modulus_pa)
  local k_b = (1 - b.poisson_ratio ^ 2) / (pi * b.young_modulus_pa)
  return 4 / (3 * pi * (k_a + k_b))
end

--- coating.effective_radius(radius_a_m, radius_b_m) -> R = r1 r2 / (r1 + r2) [m]
--- (the "radius of the contact system" after Eq. B.3; R = r/2 for equal spheres).
function M.effective_radius(radius_a_m, radius_b_m)
  local where = "coating.effective_radius"
  checks.positive(where, "radius_a_m", radius_a_m, "m")
  checks.positive(where, "radius_b_m", radius_b_m, "m")
  return radius_a_m * radius_b_m / (radius_a_m + radius_b_m)
end

--- coating.limiting_elastic_velocity(material, [other_material]) -> phi [m/s], Eq. B.1:
--- phi = (2 pi / (3 K))^2 (2 / (5 rho))^(1/2) Y^(5/2),
--- rho and Y of `material` (the impacting particle), K from Eq. B.3 for the pair
--- (other_material defaults to material: host-host impact).
--- This is the relative velocity at which the peak Hertz pressure reaches Y for
--- a sphere of `material` hitting a flat (Johnson 1985, Eq. 11.24 with p0 = Y).
--- Appendix B applies it to two equal spheres and B.4 is built so that Q_pe = 0
--- at v = phi; we keep that (it reproduces the 0.0081 m/s quoted for PMMA).
function M.limiting_elastic_velocity(material, other_material)
  local where = "coating.limiting_elastic_velocity"
  local m = material_arg(where, "material", material)
  if m.yield_stress_pa == nil then
    checks.raise(string.format("%s: material '%s' has no yield_stress_pa (Eq. B.1 needs Y)", where, m.name))
  end
  local k = M.elastic_constant(m, other_material == nil and m or other_material)
  return (2 * pi / (3 * k)) ^ 2 * math.sqrt(2 / (5 * m.density_kg_m3)) * m.yield_stress_pa ^ 2.5
end

--- coating.stored_elastic_energy { host_mass_kg, impact_velocity_m_s, limiting_elastic_velocity_m_s }
--- -> Q_pe [J], Eq. B.4 (Rogers and Reed 1984), the energy stored elastically in
--- the plastically deformed contact region:
--- Q_pe = (15 m phi^2 / 8)^(1/2) [ (2 m v^2 - m phi^2 / 8)^(1/2) - (15 m phi^2 / 8)^(1/2) ] / 2.
--- Zero at v = phi; v must be >= phi (below it the impact is elastic).
function M.stored_elastic_energy(args)
  local where = "coating.stored_elastic_energy"
  checks.table_arg(where, args, "host_mass_kg, impact_velocity_m_s, limiting_elastic_velocity_m_s")
  checks.known_keys(where, args, { "host_mass_kg", "impact_velocity_m_s", "limiting_elastic_velocity_m_s" })
  local m = checks.positive(where, "host_mass_kg", args.host_mass_kg, "kg")
  local v = checks.positive(where, "impact_velocity_m_s", args.impact_velocity_m_s, "m/s")
  local phi = checks.positive(where, "limiting_elastic_velocity_m_s", args.limiting_elastic_velocity_m_s, "m/s")
  if v < phi then
    checks.fail(where, "impact_velocity_m_s", string.format(">= the limiting elastic velocity %.4g m/s", phi), v)
  end
  local elastic_part = math.sqrt(15 * m * phi ^ 2 / 8)
  return elastic_part * (math.sqrt(2 * m * v ^ 2 - m * phi ^ 2 / 8) - elastic_part) / 2
end

--- coating.host_host_impact { host = "PMMA", host_radius_m = 200e-6, impact_velocity_m_s = 1 }
--- -> table describing the largest contact between two equal host spheres that
--- approach each other at the relative velocity v:
---   regime                           "elastic-plastic" (v >= phi) or "elastic"
---   limiting_elastic_velocity_m_s    phi, Eq. B.1
---   host_mass_kg                     m = (4/3) pi r^3 rho
---   effective_radius_m               R = r / 2
---   elastic_constant_pa              K, Eq. B.3
---   stored_elastic_energy_j          Q_pe, Eq. B.4 (0 when elastic)
---   max_contact_radius_m             a_m, Eq. B.2: (2 Q_pe / (pi Y R))^(1/2) (3 K / (2 pi Y))
---   contact_area_m2                  pi a_m^2 (Fig. 4.27)
---   total_force_n                    P = pi a_m^2 Y, Eq. B.5
---   mean_pressure_pa                 P / (pi a_m^2)
--- Below phi appendix B has no formula; we use the Hertz impact of the two
--- spheres (reduced mass m/2, E* = 3K/4): delta = (15 m* v^2 / (16 E* R^(1/2)))^(2/5),
--- a = (R delta)^(1/2), P = (4/3) E* R^(1/2) delta^(3/2). B.2 as printed goes
--- to a_m = 0 at v = phi, so the two branches do not join; the coating studies
--- run well above phi.
function M.host_host_impact(args)
  local where = "coating.host_host_impact"
  checks.table_arg(where, args, "host, host_radius_m, impact_velocity_m_s")
  checks.known_keys(where, args, { "host", "host_radius_m", "impact_velocity_m_s" })
  local host = material_arg(where, "host", args.host)
  local r = checks.positive(where, "host_radius_m", args.host_radius_m, "m")
  local v = checks.positive(where, "impact_velocity_m_s", args.impact_velocity_m_s, "m/s")
  local phi = M.limiting_elastic_velocity(host)
  local y = host.yield_stress_pa
  local k = M.elastic_constant(host, host)
  local mass = 4 / 3 * pi * r ^ 3 * host.density_kg_m3
  local big_r = r / 2
  local out = {
    limiting_elastic_velocity_m_s = phi,
    host_mass_kg = mass,
    effective_radius_m = big_r,
    elastic_constant_pa = k,
    impact_velocity_m_s = v,
  }
  if v >= phi then
    out.regime = "elastic-plastic"
    local q = M.stored_elastic_energy { host_mass_kg = mass, impact_velocity_m_s = v,
                                        limiting_elastic_velocity_m_s = phi }
    out.stored_elastic_energy_j = q
    out.max_contact_radius_m = math.sqrt(2 * q / (pi * y * big_r)) * (3 * k / (2 * pi * y))  -- B.2
    out.total_force_n = pi * out.max_contact_radius_m ^ 2 * y                                 -- B.5
  else
    out.regime = "elastic"
    out.stored_elastic_energy_j = 0
    local reduced_mass = mass / 2
    local e_star = 3 * k / 4
    local delta = (15 * reduced_mass * v ^ 2 / (16 * e_star * math.sqrt(big_r))) ^ 0.4
    out.max_contact_radius_m = math.sqrt(big_r * delta)
    out.total_force_n = 4 / 3 * e_star * math.sqrt(big_r) * delta ^ 1.5
  end
  out.contact_area_m2 = pi * out.max_contact_radius_m ^ 2
  out.mean_pressure_pa = out.total_force_n / out.contact_area_m2
  return out
end

--- coating.guest_number_density(guest_radius_m, [packing_ratio]) -> n_g [1/m^2]:
--- guests per unit host surface, n_g = packing_ratio / (pi r^2) (after Eq. B.6).
function M.guest_number_density(guest_radius_m, packing_ratio)
  local where = "coating.guest_number_density"
  checks.positive(where, "guest_radius_m", guest_radius_m, "m")
  packing_ratio = packing_ratio == nil and M.DEFAULT_PACKING_RATIO or packing_ratio
  checks.half_open(where, "packing_ratio", packing_ratio, 0, 1)
  return packing_ratio / (pi * guest_radius_m ^ 2)
end

--- coating.force_per_guest { total_force_n, max_contact_radius_m, guest_radius_m, [packing_ratio = 0.79] }
--- -> F [N], Eq. B.6: F = P / (n_g pi a_m^2), the host-host force shared by the
--- guests inside the contact. With P = pi a_m^2 Y (B.5) this is Y / n_g: it does
--- not depend on the impact velocity (the flat curve of Fig. 4.28).
function M.force_per_guest(args)
  local where = "coating.force_per_guest"
  checks.table_arg(where, args, "total_force_n, max_contact_radius_m, guest_radius_m, packing_ratio")
  checks.known_keys(where, args, { "total_force_n", "max_contact_radius_m", "guest_radius_m", "packing_ratio" })
  local p = checks.positive(where, "total_force_n", args.total_force_n, "N")
  local a = checks.positive(where, "max_contact_radius_m", args.max_contact_radius_m, "m")
  local n_g = M.guest_number_density(args.guest_radius_m, args.packing_ratio)
  return p / (n_g * pi * a ^ 2)
end

--- coating.work_of_adhesion(material_a, material_b) -> gamma [J/m^2], Eq. B.9:
--- gamma = 2 (omega_d1 omega_d2)^(1/2) + 2 (omega_p1 omega_p2)^(1/2),
--- from the dispersive and polar surface energies (geometric-mean rule). This
--- is the gamma that enters the JKR equations B.8 and B.10.
function M.work_of_adhesion(material_a, material_b)
  local where = "coating.work_of_adhesion"
  local a = material_arg(where, "material_a", material_a)
  local b = material_arg(where, "material_b", material_b == nil and material_a or material_b)
  return 2 * math.sqrt(a.surface_energy_dispersive_j_m2 * b.surface_energy_dispersive_j_m2)
       + 2 * math.sqrt(a.surface_energy_polar_j_m2 * b.surface_energy_polar_j_m2)
end

local function contact_args(where, args, with_adhesion)
  local keys = { "force_n", "effective_radius_m", "elastic_constant_pa" }
  if with_adhesion then keys[#keys + 1] = "work_of_adhesion_j_m2" end
  checks.table_arg(where, args, table.concat(keys, ", "))
  checks.known_keys(where, args, keys)
  local f = checks.non_negative(where, "force_n", args.force_n, "N")
  local r = checks.positive(where, "effective_radius_m", args.effective_radius_m, "m")
  local k = checks.positive(where, "elastic_constant_pa", args.elastic_constant_pa, "Pa")
  local gamma = 0
  if with_adhesion then gamma = checks.non_negative(where, "work_of_adhesion_j_m2", args.work_of_adhesion_j_m2, "J/m^2") end
  return f, r, k, gamma
end

--- coating.hertz_contact { force_n, effective_radius_m, elastic_constant_pa }
--- -> { contact_radius_m, central_displacement_m }: Eq. B.7, a_h = (R' F / K')^(1/3),
--- and the Hertz central displacement delta_h = a_h^2 / R' (B.10 with gamma = 0).
function M.hertz_contact(args)
  local f, r, k = contact_args("coating.hertz_contact", args, false)
  local a = (r * f / k) ^ (1 / 3)
  return { contact_radius_m = a, central_displacement_m = a ^ 2 / r }
end

--- coating.jkr_contact { force_n, effective_radius_m, elastic_constant_pa, work_of_adhesion_j_m2 }
--- -> { contact_radius_m, central_displacement_m }: Eq. B.8,
--- a_j^3 = (R'/K') [F + 3 gamma pi R' + (6 gamma pi R' F + (3 gamma pi R')^2)^(1/2)],
--- and Eq. B.10, delta_j = a_j^2 / R' - (8 pi gamma a_j / (3 K'))^(1/2).
--- With gamma = 0 both reduce to the Hertz values of hertz_contact.
function M.jkr_contact(args)
  local f, r, k, gamma = contact_args("coating.jkr_contact", args, true)
  local adhesion = 3 * gamma * pi * r
  local a = (r / k * (f + adhesion + math.sqrt(6 * gamma * pi * r * f + adhesion ^ 2))) ^ (1 / 3)
  return { contact_radius_m = a, central_displacement_m = a ^ 2 / r - math.sqrt(8 * pi * gamma * a / (3 * k)) }
end

--- coating.central_displacement_ratio(central_displacement_m, guest_radius_m) -> delta / (2 r_g):
--- the "deformation level" of section 4.6, central displacement over guest diameter.
function M.central_displacement_ratio(central_displacement_m, guest_radius_m)
  local where = "coating.central_displacement_ratio"
  checks.number(where, "central_displacement_m", central_displacement_m, "m")
  checks.positive(where, "guest_radius_m", guest_radius_m, "m")
  return central_displacement_m / (2 * guest_radius_m)
end

--- coating.guest_deformation { host, guest, host_radius_m, guest_radius_m, impact_velocity_m_s,
---                             [packing_ratio = 0.79] }
--- -> the whole appendix B chain for rigid guests on a soft host: every field of
--- host_host_impact plus
---   force_per_guest_n                 F, Eq. B.6
---   host_guest_effective_radius_m     R'
---   host_guest_elastic_constant_pa    K', Eq. B.3 for host and guest
---   work_of_adhesion_j_m2             gamma, Eq. B.9
---   hertz_contact_radius_m, hertz_central_displacement_m, hertz_central_displacement_ratio  (B.7)
---   jkr_contact_radius_m,   jkr_central_displacement_m,   jkr_central_displacement_ratio    (B.8-B.10)
function M.guest_deformation(args)
  local where = "coating.guest_deformation"
  checks.table_arg(where, args, "host, guest, host_radius_m, guest_radius_m, impact_velocity_m_s, packing_ratio")
  checks.known_keys(where, args, { "host", "guest", "host_radius_m", "guest_radius_m", "impact_velocity_m_s",
                                   "packing_ratio" })
  local host = material_arg(where, "host", args.host)
  local guest = material_arg(where, "guest", args.guest)
  local r_guest = checks.positive(where, "guest_radius_m", args.guest_radius_m, "m")
  local out = M.host_host_impact { host = host, host_radius_m = args.host_radius_m,
                                   impact_velocity_m_s = args.impact_velocity_m_s }
  out.force_per_guest_n = M.force_per_guest { total_force_n = out.total_force_n,
    max_contact_radius_m = out.max_contact_radius_m, guest_radius_m = r_guest,
    packing_ratio = args.packing_ratio }
  out.host_guest_effective_radius_m = M.effective_radius(args.host_radius_m, r_guest)
  out.host_guest_elastic_constant_pa = M.elastic_constant(host, guest)
  out.work_of_adhesion_j_m2 = M.work_of_adhesion(host, guest)
  local hertz = M.hertz_contact { force_n = out.force_per_guest_n,
    effective_radius_m = out.host_guest_effective_radius_m,
    elastic_constant_pa = out.host_guest_elastic_constant_pa }
  local jkr = M.jkr_contact { force_n = out.force_per_guest_n,
    effective_radius_m = out.host_guest_effective_radius_m,
    elastic_constant_pa = out.host_guest_elastic_constant_pa,
    work_of_adhesion_j_m2 = out.work_of_adhesion_j_m2 }
  out.hertz_contact_radius_m = hertz.contact_radius_m
  out.hertz_central_displacement_m = hertz.central_displacement_m
  out.hertz_central_displacement_ratio = M.central_displacement_ratio(hertz.central_displacement_m, r_guest)
  out.jkr_contact_radius_m = jkr.contact_radius_m
  out.jkr_central_displacement_m = jkr.central_displacement_m
  out.jkr_central_displacement_ratio = M.central_displacement_ratio(jkr.central_displacement_m, r_guest)
  return out
end

--- coating.max_force_slope { particle_mass_kg, stiffness_n_m, [impact_angle_deg = 0] } -> c [N s/m]
--- in F_max = c dv (section 7.2; Fig. 4.26) for two equal spheres with a linear
--- loading spring K (Walton-Braun K1): the normal approach speed dv cos(alpha)
--- is stopped by the spring with the reduced mass m/2, so
--- F_max = K delta_max = dv cos(alpha) (K m / 2)^(1/2). Table 3.1 gives c = 0.0201 N s/m head-on,
--- the 0.02 of section 7.2. Friction and spin change the normal force only
--- through the model's coupling, which Walton-Braun does not have.
function M.max_force_slope(args)
  local where = "coating.max_force_slope"
  checks.table_arg(where, args, "particle_mass_kg, stiffness_n_m, impact_angle_deg")
  checks.known_keys(where, args, { "particle_mass_kg", "stiffness_n_m", "impact_angle_deg" })
  local m = checks.positive(where, "particle_mass_kg", args.particle_mass_kg, "kg")
  local k = checks.positive(where, "stiffness_n_m", args.stiffness_n_m, "N/m")
  local angle = args.impact_angle_deg == nil and 0 or args.impact_angle_deg
  checks.number(where, "impact_angle_deg", angle, "deg")
  if angle < 0 or angle >= 90 then checks.fail(where, "impact_angle_deg", "in [0, 90) deg", angle) end
  return math.sqrt(k * m / 2) * math.cos(math.rad(angle))
end

--- coating.minimum_time { collisions = list or iterator, host_count = N, host_radius_m = r,
---                        [patches_per_contact = 1], [contact_radius = "effective"] }
--- -> time_s, details   or   nil, message, details
--- Section 4.7: walk the host-host collisions in time order, add the contact
--- area pi a^2 with a = (d R)^(1/2) of each, and return the time of the
--- collision at which the sum first reaches the total host surface N 4 pi r^2.
--- Each collision is a table { time_s = t, max_overlap_m = d, effective_radius_m = R }
--- (d: the maximum central displacement, i.e. overlap, of that contact).
--- `collisions` is a list (sorted here by time, the list is not changed) or an
--- iterator function returning one collision per call and nil at the end (it
--- must come in non-decreasing time). The dissertation counts one patch per
--- contact although a contact marks both hosts; patches_per_contact = 2 counts
--- both. The text's a = (d R)^(1/2) does not say which R: contact_radius =
--- "effective" takes each collision's R* (Hertz's a^2 = R* d), "host" the
--- host radius r (2 R* for equal hosts). The four readings of 4.7 are these
--- two choices crossed. details = { covered_area_m2, target_area_m2, collisions_used }.
--- When the collisions never cover the surface: nil, a message, details.
function M.minimum_time(args)
  local where = "coating.minimum_time"
  checks.table_arg(where, args, "collisions, host_count, host_radius_m, patches_per_contact")
  checks.known_keys(where, args, { "collisions", "host_count", "host_radius_m", "patches_per_contact",
                                   "contact_radius" })
  local n = checks.positive(where, "host_count", args.host_count, "-")
  if math.type(n) ~= "integer" and n ~= math.floor(n) then checks.fail(where, "host_count", "a whole number", n) end
  local r = checks.positive(where, "host_radius_m", args.host_radius_m, "m")
  local patches = args.patches_per_contact == nil and 1 or args.patches_per_contact
  checks.positive(where, "patches_per_contact", patches, "-")
  local radius_choice = args.contact_radius == nil and "effective" or args.contact_radius
  if radius_choice ~= "effective" and radius_choice ~= "host" then
    checks.fail(where, "contact_radius", "'effective' (R*) or 'host' (r)", radius_choice)
  end
  local target = n * 4 * pi * r ^ 2

  local next_collision
  if type(args.collisions) == "table" then
    local sorted = {}
    for k, c in ipairs(args.collisions) do
      if type(c) ~= "table" then checks.fail(where, string.format("collisions[%d]", k), "a table", c) end
      sorted[k] = { index = k, record = c }
    end
    for _, entry in ipairs(sorted) do
      checks.number(where, string.format("collisions[%d].time_s", entry.index), entry.record.time_s, "s")
    end
    table.sort(sorted, function(x, y)
      if x.record.time_s ~= y.record.time_s then return x.record.time_s < y.record.time_s end
      return x.index < y.index
    end)
    local position = 0
    next_collision = function()
      position = position + 1
      local entry = sorted[position]
      if entry then return entry.record, entry.index end
      return nil
    end
  elseif type(args.collisions) == "function" then
    local count = 0
    next_collision = function()
      local c = args.collisions()
      if c == nil then return nil end
      count = count + 1
      return c, count
    end
  else
    checks.fail(where, "collisions", "a list of collisions or an iterator function", args.collisions)
  end

  local covered, used, last_time = 0, 0, -math.huge
  while true do
    local c, index = next_collision()
    if c == nil then break end
    local name = string.format("collisions[%d]", index)
    if type(c) ~= "table" then checks.fail(where, name, "a table", c) end
    checks.known_keys(where, c, { "time_s", "max_overlap_m", "effective_radius_m" })
    local t = checks.number(where, name .. ".time_s", c.time_s, "s")
    local d = checks.non_negative(where, name .. ".max_overlap_m", c.max_overlap_m, "m")
    local big_r = checks.positive(where, name .. ".effective_radius_m", c.effective_radius_m, "m")
    if t < last_time then
      checks.fail(where, name .. ".time_s", string.format(">= the previous collision's time %.6g s", last_time), t)
    end
    last_time = t
    used = used + 1
    if radius_choice == "host" then big_r = r end
    covered = covered + patches * pi * d * big_r   -- pi a^2 with a^2 = d R (section 4.7)
    if covered >= target then
      return t, { covered_area_m2 = covered, target_area_m2 = target, collisions_used = used }
    end
  end
  local details = { covered_area_m2 = covered, target_area_m2 = target, collisions_used = used }
  return nil, string.format("%s: the %d collisions cover %.4g m^2, %.3g %% of the host surface %.4g m^2",
    where, used, covered, 100 * covered / target, target), details
end

return M
