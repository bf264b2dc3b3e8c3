-- granule.coating against appendix B and sections 4.6-4.7: the PMMA limiting
-- elastic velocity, Rogers-Reed, the force per guest, Hertz and JKR contacts,
-- the minimum coating time on collision lists worked out by hand, and the
-- F_max = c dv slope of the binary impact (section 7.2) against the engine.
local H = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/helpers.lua")
local coating = require "granule.coating"
local materials = require "granule.materials"

local pi = math.pi
local pmma = materials.get("PMMA")

-- B.1: "as small as 0.0081 m/s" for PMMA; two digits = +- half a unit in the second.
local phi = coating.limiting_elastic_velocity("PMMA")
H.near(phi, 0.0081, 0.5e-4, "Eq. B.1 limiting elastic velocity of PMMA")

-- B.1 is Johnson's (Contact Mechanics, 11.24) first yield of a sphere on a flat:
-- peak Hertz pressure p0 = 2 E* (delta/R)^(1/2) / pi reaches Y when the kinetic
-- energy (1/2) m v^2 equals the elastic work (8/15) E* R^(1/2) delta^(5/2).
-- An independent derivation, with E* = 3 K / 4 (K of B.3).
local k_host = coating.elastic_constant("PMMA", "PMMA")
H.relative(k_host, 2 / 3 * pmma.young_modulus_pa / (1 - pmma.poisson_ratio ^ 2), 1e-12,
  "B.3 for one material: K = (2/3) E / (1 - nu^2)")
do
  local e_star, radius, y = 3 * k_host / 4, 1e-4, pmma.yield_stress_pa
  local delta_y = radius * (pi * y / (2 * e_star)) ^ 2
  local mass = 4 / 3 * pi * radius ^ 3 * pmma.density_kg_m3
  local v_y = math.sqrt(2 * (8 / 15) * e_star * math.sqrt(radius) * delta_y ^ 2.5 / mass)
  H.relative(phi, v_y, 1e-12, "B.1 = first yield of Hertz impact (p0 = Y)")
end

-- B.4: no stored plastic-region energy at v = phi, growing with v.
local mass = 4 / 3 * pi * (200e-6) ^ 3 * pmma.density_kg_m3
H.near(coating.stored_elastic_energy { host_mass_kg = mass, impact_velocity_m_s = phi,
  limiting_elastic_velocity_m_s = phi }, 0, 1e-25, "Q_pe(v = phi) = 0")
local impact_1 = coating.host_host_impact { host = "PMMA", host_radius_m = 200e-6, impact_velocity_m_s = 1 }
local impact_10 = coating.host_host_impact { host = "PMMA", host_radius_m = 200e-6, impact_velocity_m_s = 10 }
H.check(impact_1.regime == "elastic-plastic", "1 m/s is beyond the elastic limit")
H.check(impact_10.stored_elastic_energy_j > impact_1.stored_elastic_energy_j, "Q_pe grows with v")
-- B.2 and B.5 by hand at 1 m/s.
do
  local y, r_eff = pmma.yield_stress_pa, 100e-6
  local q = math.sqrt(15 * mass * phi ^ 2 / 8)
            * (math.sqrt(2 * mass - mass * phi ^ 2 / 8) - math.sqrt(15 * mass * phi ^ 2 / 8)) / 2
  H.relative(impact_1.stored_elastic_energy_j, q, 1e-12, "Eq. B.4 at 1 m/s")
  local a_m = math.sqrt(2 * q / (pi * y * r_eff)) * 3 * k_host / (2 * pi * y)
  H.relative(impact_1.max_contact_radius_m, a_m, 1e-12, "Eq. B.2 at 1 m/s")
  H.relative(impact_1.total_force_n, pi * a_m ^ 2 * y, 1e-12, "Eq. B.5 at 1 m/s")
end
-- Fig. 4.27: for v >> phi the contact area grows linearly with v (Q_pe ~ v).
H.relative(impact_10.contact_area_m2 / impact_1.contact_area_m2, 10, 0.01, "contact area ~ v (Fig. 4.27)")

-- Below phi: the Hertz impact of two equal spheres; its elastic work equals
-- the kinetic energy of the relative motion (reduced mass m/2).
do
  local slow = coating.host_host_impact { host = "PMMA", host_radius_m = 200e-6, impact_velocity_m_s = phi / 2 }
  H.check(slow.regime == "elastic", "below phi the impact is elastic")
  local delta = slow.max_contact_radius_m ^ 2 / slow.effective_radius_m
  local work = 8 / 15 * (3 * k_host / 4) * math.sqrt(slow.effective_radius_m) * delta ^ 2.5
  H.relative(work, 0.5 * (mass / 2) * (phi / 2) ^ 2, 1e-12, "Hertz impact energy balance below phi")
end

-- B.6: with P = pi a_m^2 Y the force per guest is Y / n_g, whatever the velocity (Fig. 4.28).
local guest_r = 2.5e-6
local f_guest = coating.force_per_guest { total_force_n = impact_1.total_force_n,
  max_contact_radius_m = impact_1.max_contact_radius_m, guest_radius_m = guest_r }
H.relative(f_guest, pmma.yield_stress_pa * pi * guest_r ^ 2 / 0.79, 1e-12, "B.6 force per guest = Y pi r^2 / 0.79")
local f_guest_10 = coating.force_per_guest { total_force_n = impact_10.total_force_n,
  max_contact_radius_m = impact_10.max_contact_radius_m, guest_radius_m = guest_r }
H.relative(f_guest_10, f_guest, 1e-12, "force per guest independent of v beyond phi")

-- B.9 from the dispersive and polar parts of Table 4.2.
local gamma = coating.work_of_adhesion("PMMA", "Al2O3")
H.relative(gamma, 2 * math.sqrt(35.9e-3 * 1.0) + 2 * math.sqrt(4.3e-3 * 0.54), 1e-12, "Eq. B.9 PMMA-Al2O3")
H.relative(coating.work_of_adhesion("Al2O3", "PMMA"), gamma, 1e-15, "B.9 is symmetric")
H.relative(coating.work_of_adhesion("PMMA", "PMMA"), 2 * (35.9e-3 + 4.3e-3), 1e-12,
  "B.9 for one material: twice its surface energy (work of cohesion)")

-- B.7-B.10: JKR reduces to Hertz when the surface energy is zero.
local k_hg = coating.elastic_constant("PMMA", "Al2O3")
local r_hg = coating.effective_radius(200e-6, guest_r)
local contact = { force_n = f_guest, effective_radius_m = r_hg, elastic_constant_pa = k_hg }
local hertz = coating.hertz_contact(contact)
H.relative(hertz.contact_radius_m, (r_hg * f_guest / k_hg) ^ (1 / 3), 1e-12, "Eq. B.7")
local jkr_zero = coating.jkr_contact { force_n = f_guest, effective_radius_m = r_hg, elastic_constant_pa = k_hg,
                                      work_of_adhesion_j_m2 = 0 }
H.relative(jkr_zero.contact_radius_m, hertz.contact_radius_m, 1e-12, "JKR contact radius at gamma = 0")
H.relative(jkr_zero.central_displacement_m, hertz.central_displacement_m, 1e-12, "JKR displacement at gamma = 0")
do  -- the same through the whole chain, with surface-energy-free copies of the materials
  materials.define { name = "PMMA_clean", base = "PMMA", surface_energy_dispersive_j_m2 = 0,
                     surface_energy_polar_j_m2 = 0 }
  local d = coating.guest_deformation { host = "PMMA_clean", guest = "Al2O3", host_radius_m = 200e-6,
                                        guest_radius_m = guest_r, impact_velocity_m_s = 1 }
  H.relative(d.jkr_central_displacement_ratio, d.hertz_central_displacement_ratio, 1e-12,
    "guest_deformation: JKR = Hertz without surface energy")
end
-- With adhesion the B.8 radius satisfies the JKR load relation F = K a^3/R - (6 pi gamma K a^3)^(1/2)
-- (Johnson-Kendall-Roberts 1971, with K = 4 E*/3), and B.10 is their approach.
local jkr = coating.jkr_contact { force_n = f_guest, effective_radius_m = r_hg, elastic_constant_pa = k_hg,
                                  work_of_adhesion_j_m2 = gamma }
do
  local a = jkr.contact_radius_m
  H.relative(k_hg * a ^ 3 / r_hg - math.sqrt(6 * pi * gamma * k_hg * a ^ 3), f_guest, 1e-9, "B.8 solves JKR")
  H.relative(jkr.central_displacement_m, a ^ 2 / r_hg - math.sqrt(8 * pi * gamma * a / (3 * k_hg)), 1e-12, "B.10")
  H.check(a > hertz.contact_radius_m, "adhesion widens the contact")
end

-- Trends of Figs 4.28-4.30.
local function ratio(guest_radius, host, v)
  return coating.guest_deformation { host = host or "PMMA", guest = "Al2O3", host_radius_m = 200e-6,
    guest_radius_m = guest_radius, impact_velocity_m_s = v or 1 }
end
H.relative(ratio(guest_r, nil, 5).jkr_central_displacement_ratio, ratio(guest_r, nil, 0.1).jkr_central_displacement_ratio,
  1e-12, "Fig. 4.28: the ratio does not depend on v beyond phi")
H.check(ratio(0.5e-6).jkr_central_displacement_ratio > ratio(5e-6).jkr_central_displacement_ratio,
  "Fig. 4.29: smaller guests sink deeper (relative to their size)")
H.relative(ratio(0.5e-6).hertz_central_displacement_ratio, ratio(5e-6).hertz_central_displacement_ratio, 0.03,
  "Fig. 4.29: without adhesion the ratio hardly depends on guest size (F ~ r^2, R' ~ r)")
materials.define { name = "PMMA_hard", base = "PMMA", young_modulus_pa = 2 * pmma.young_modulus_pa }
local soft, hard = ratio(guest_r), ratio(guest_r, "PMMA_hard")
H.check(hard.jkr_central_displacement_ratio < soft.jkr_central_displacement_ratio, "Fig. 4.30: harder host, less deformation")
H.relative(hard.hertz_central_displacement_ratio / soft.hertz_central_displacement_ratio,
  (soft.host_guest_elastic_constant_pa / hard.host_guest_elastic_constant_pa) ^ (2 / 3), 1e-12,
  "Hertz displacement ~ K'^(-2/3) at equal force")

-- Section 7.2's c = 0.02 N s/m: the linear-spring slope for Table 3.1.
local m31 = 4 / 3 * pi * (0.2e-3) ^ 3 * 1200
local c0 = coating.max_force_slope { particle_mass_kg = m31, stiffness_n_m = 20000 }
H.near(c0, 0.02, 0.0005, "F_max / dv head-on for Table 3.1 (section 7.2)")
H.relative(coating.max_force_slope { particle_mass_kg = m31, stiffness_n_m = 20000, impact_angle_deg = 60 }, c0 / 2,
  1e-12, "slope ~ cos(angle)")
-- ... and the engine's Walton-Braun impact gives it (one head-on and one oblique run).
for _, case in ipairs { { angle = 0, v = 1.0 }, { angle = 60, v = 0.5 } } do
  local sim = simulation { dimension = 2, record_contacts = true }
  sim:material { name = "p", density = 1200 }
  sim:contact { "p", "p", model = "walton_braun", k_load = 20000, restitution = 0.85, friction = 0.4 }
  local dir = { math.cos(math.rad(case.angle)), math.sin(math.rad(case.angle)) }
  -- Start each sphere a short time back along its path from the touching
  -- position (+-r, 0), so that at first contact the line of centres is x and
  -- the impact angle is the nominal one (starting side by side instead would
  -- tilt it by the sideways drift during the approach).
  local back = 4e-6 / (case.v * dir[1])
  sim:add_particle { position = { -0.2e-3 - dir[1] * case.v / 2 * back, -dir[2] * case.v / 2 * back },
                     radius = 0.2e-3, material = "p", velocity = { dir[1] * case.v / 2, dir[2] * case.v / 2 } }
  sim:add_particle { position = { 0.2e-3 + dir[1] * case.v / 2 * back, dir[2] * case.v / 2 * back },
                     radius = 0.2e-3, material = "p", velocity = { -dir[1] * case.v / 2, -dir[2] * case.v / 2 } }
  local f_max, seen, done = 0, false, false
  sim:every { steps = 1, function(s)
    local list = s:contacts()
    if #list > 0 then
      seen = true
      f_max = math.max(f_max, list[1].normal_force)
    elseif seen then
      done = true
    end
  end }
  sim:run { duration = 1e-4, check_every = 1, stop_when = function() return done end }
  H.check(done, "the engine's impact finished")
  local expected = coating.max_force_slope { particle_mass_kg = m31, stiffness_n_m = 20000,
                                             impact_angle_deg = case.angle } * case.v
  -- 40 steps per contact resolve the force peak of a half sine to 1 - cos(pi/40) ~ 0.3 %; in an
  -- oblique contact the line of centres also turns by ~ v_t t_c / (2 r), a few 1e-3 rad.
  H.relative(f_max, expected, 0.01, string.format("engine F_max at %g deg, %g m/s", case.angle, case.v))
end

-- Section 4.7, minimum coating time, on lists worked out by hand.
-- 3 hosts of r = 0.2 mm: the surface is 3 * 4 pi r^2, so the patches must add
-- up to sum(d R) = 12 r^2 = 4.8e-7 m^2. Every collision below has d R = 4e-10 m^2
-- except that the host radius is chosen so the target needs 1199.5 of them:
-- the sum first reaches it at the 1200th collision, at t = 1200 ms.
local r_host = math.sqrt(1199.5 * 4e-10 / 12)
local function collision(k) return { time_s = k * 1e-3, max_overlap_m = 4e-6, effective_radius_m = 1e-4 } end
local list = {}
for k = 1, 1500 do list[k] = collision(k) end
local t, details = coating.minimum_time { collisions = list, host_count = 3, host_radius_m = r_host }
H.near(t, 1.2, 1e-12, "minimum coating time, 1200th collision")
H.check(details.collisions_used == 1200, "1200 collisions used, got " .. tostring(details.collisions_used))
H.relative(details.target_area_m2, 3 * 4 * pi * r_host ^ 2, 1e-12, "target area N 4 pi r^2")
-- Counting both hosts' patches halves the count: the 600th collision.
t = coating.minimum_time { collisions = list, host_count = 3, host_radius_m = r_host, patches_per_contact = 2 }
H.near(t, 0.6, 1e-12, "two patches per contact, 600th collision")
-- The four readings of 4.7 on a hand-counted list: one host of r = 1 mm (surface
-- 4 pi r^2), collisions with d R* = r^2 / 2 each, i.e. pi r^2 / 2 for one patch and R*:
-- eight collisions cover it; two patches or R = r (= 2 R* here, d r = r^2) four; both two.
do
  local r1 = 1e-3
  local hand = {}
  for i = 1, 10 do hand[i] = { time_s = i * 0.1, max_overlap_m = r1, effective_radius_m = r1 / 2 } end
  for _, case in ipairs { { 1, "effective", 8 }, { 2, "effective", 4 }, { 1, "host", 4 }, { 2, "host", 2 } } do
    local tc = coating.minimum_time { collisions = hand, host_count = 1, host_radius_m = r1,
                                      patches_per_contact = case[1], contact_radius = case[2] }
    H.near(tc, case[3] * 0.1, 1e-12, string.format("%d patch(es), contact_radius=%s: collision %d", case[1], case[2],
      case[3]))
  end
  H.fails("contact_radius", coating.minimum_time, { collisions = hand, host_count = 1, host_radius_m = r1,
    contact_radius = "r" })
end
-- The same from an iterator.
local k = 0
t = coating.minimum_time { collisions = function() k = k + 1 if k <= 1500 then return collision(k) end end,
                           host_count = 3, host_radius_m = r_host }
H.near(t, 1.2, 1e-12, "iterator input")
-- Order does not matter for a list (sorted by time), and the list is not changed.
local shuffled = {}
for i = 1500, 1, -1 do shuffled[#shuffled + 1] = list[i] end
t = coating.minimum_time { collisions = shuffled, host_count = 3, host_radius_m = r_host }
H.near(t, 1.2, 1e-12, "reversed list")
H.check(shuffled[1].time_s == 1.5, "the caller's list keeps its order")
-- One large contact covers everything at once; unequal contacts add up: a = (d R)^(1/2).
t = coating.minimum_time { collisions = { { time_s = 0.25, max_overlap_m = 1e-3, effective_radius_m = 1e-3 } },
                           host_count = 1, host_radius_m = 0.5e-3 }   -- pi 1e-6 >= 4 pi 0.25e-6: equal, reached
H.near(t, 0.25, 0, "one contact exactly covering the surface")
t = coating.minimum_time { collisions = {
    { time_s = 0.1, max_overlap_m = 1e-6, effective_radius_m = 1e-4 },   -- d R = 1e-10
    { time_s = 0.2, max_overlap_m = 2e-6, effective_radius_m = 1e-4 },   -- 2e-10, sum 3e-10
    { time_s = 0.3, max_overlap_m = 4e-6, effective_radius_m = 0.5e-4 }, -- 2e-10, sum 5e-10
  }, host_count = 1, host_radius_m = math.sqrt(4e-10 / 4) }              -- target sum d R = 4e-10
H.near(t, 0.3, 0, "unequal contacts: reached at the third")
-- Never reached: nil, a message and how far it got.
local none, message, partial = coating.minimum_time { collisions = { collision(1), collision(2) },
                                                      host_count = 1500, host_radius_m = 0.2e-3 }
H.check(none == nil and type(message) == "string" and message:find("%%"), "not reached: nil and a message")
H.relative(partial.covered_area_m2, 2 * pi * 4e-10, 1e-12, "area covered by two collisions")
H.check(coating.minimum_time { collisions = {}, host_count = 1, host_radius_m = 1e-3 } == nil, "no collisions")
-- Bad records are named.
H.fails("collisions[2].max_overlap_m", coating.minimum_time, { collisions = { collision(1),
  { time_s = 0.002, max_overlap_m = -1, effective_radius_m = 1e-4 } }, host_count = 1, host_radius_m = 1e-3 })
local back = { collision(2), collision(1) }
local i = 0
H.fails("time_s", coating.minimum_time, { collisions = function() i = i + 1 return back[i] end,
                                          host_count = 1, host_radius_m = 1e-3 })
H.fails("host_count", coating.minimum_time, { collisions = list, host_count = 2.5, host_radius_m = 1e-3 })

-- Bad input elsewhere is refused with the parameter's name.
H.fails("impact_velocity_m_s", coating.host_host_impact, { host = "PMMA", host_radius_m = 1e-4, impact_velocity_m_s = -1 })
H.fails("host_radius_m", coating.guest_deformation, { host = "PMMA", guest = "Al2O3", host_radius_m = 0 / 0,
  guest_radius_m = 1e-6, impact_velocity_m_s = 1 })
H.fails("did you mean 'Al2O3'", coating.guest_deformation, { host = "PMMA", guest = "AL2O3x", host_radius_m = 1e-4,
  guest_radius_m = 1e-6, impact_velocity_m_s = 1 })
H.fails("no yield_stress_pa", coating.limiting_elastic_velocity, "Al2O3")
H.fails("work_of_adhesion_j_m2", coating.jkr_contact, { force_n = 1, effective_radius_m = 1, elastic_constant_pa = 1,
  work_of_adhesion_j_m2 = -1 })
H.fails("packing_ratio", coating.force_per_guest, { total_force_n = 1, max_contact_radius_m = 1, guest_radius_m = 1,
  packing_ratio = 1.5 })

print("analysis.coating ok")
