-- Appendix B deformation numbers for one host-host impact, and (with
-- -D collisions=FILE.csv) the minimum coating time of section 4.7.
--
--   granule run tools/coating.lua                                  # PMMA 400 um + Al2O3 5 um at 1 m/s
--   granule run tools/coating.lua -D velocity=0.2 -D guest_radius=1e-6
--   granule run tools/coating.lua -D host_young=6.6e9              # a harder host (Fig. 4.30)
--   granule run tools/coating.lua -D collisions=contacts.csv -D hosts=1500 -D host_radius=0.2e-3
--
-- The collisions file is CSV with a header naming at least the columns
-- time_s, max_overlap_m, effective_radius_m (one row per host-host contact).
local coating = require "granule.coating"
local materials = require "granule.materials"

local p = parameters {
  host = { default = "PMMA", doc = "host material (granule.materials name)" },
  guest = { default = "Al2O3", doc = "guest material" },
  host_radius = { default = 200e-6, unit = "m", doc = "host particle radius (Table 4.2: 400 um diameter)" },
  guest_radius = { default = 2.5e-6, unit = "m", doc = "guest particle radius (5 um diameter)" },
  velocity = { default = 1.0, unit = "m/s", doc = "relative impact velocity of the two hosts" },
  packing_ratio = { default = coating.DEFAULT_PACKING_RATIO, above = 0, max = 1, unit = "-", doc = "guest coverage of the host surface (B.6), in (0, 1]" },
  host_young = { default = 0, unit = "Pa", doc = "override the host's Young's modulus (0: material's)" },
  host_yield = { default = 0, unit = "Pa", doc = "override the host's yield stress (0: material's)" },
  collisions = { default = "", doc = "CSV of host-host collisions for the minimum coating time (4.7)" },
  hosts = { default = 1500, integer = true, min = 1, unit = "-", doc = "number of host particles N (4.7; with collisions)" },
  patches_per_contact = { default = 1, above = 0, unit = "-", doc = "contact patches counted per collision (4.7: 1; with collisions)" },
}
-- hosts and patches_per_contact only enter the minimum coating time, which
-- needs the collisions file: given without it they would change nothing.
if p.collisions == "" and (p.hosts ~= 1500 or p.patches_per_contact ~= 1) then
  error(string.format("hosts=%g and patches_per_contact=%g are for the minimum coating time: give " ..
    "-D collisions=FILE.csv with them", p.hosts, p.patches_per_contact))
end

local host = materials.get(p.host)
if p.host_young ~= 0 then host.young_modulus_pa = p.host_young end
if p.host_yield ~= 0 then host.yield_stress_pa = p.host_yield end
host.name = host.name .. ((p.host_young ~= 0 or p.host_yield ~= 0) and " (modified)" or "")

local d = coating.guest_deformation { host = host, guest = p.guest, host_radius_m = p.host_radius,
                                      guest_radius_m = p.guest_radius, impact_velocity_m_s = p.velocity,
                                      packing_ratio = p.packing_ratio }

local function row(label, value, unit, source)
  local text = type(value) == "number" and string.format("%.5g", value) or tostring(value)
  print(string.format("  %-40s %14s %-6s %s", label, text, unit, source))
end
print(string.format("Appendix B: %s host (r = %g m) and %s guest (r = %g m), relative impact velocity %g m/s",
  host.name, p.host_radius, p.guest, p.guest_radius, p.velocity))
print(string.format("  %-40s %14s %-6s %s", "quantity", "value", "unit", "source"))
row("host yield stress Y", host.yield_stress_pa, "Pa", host.source)
row("limiting elastic velocity phi", d.limiting_elastic_velocity_m_s, "m/s", "Eq. B.1")
row("impact regime", d.regime, "", "v >= phi: Rogers-Reed")
row("host mass m", d.host_mass_kg, "kg", "(4/3) pi r^3 rho")
row("host-host elastic constant K", d.elastic_constant_pa, "Pa", "Eq. B.3")
row("host-host effective radius R", d.effective_radius_m, "m", "r / 2")
row("stored elastic energy Q_pe", d.stored_elastic_energy_j, "J", "Eq. B.4")
row("max contact radius a_m", d.max_contact_radius_m, "m", "Eq. B.2")
row("contact area pi a_m^2", d.contact_area_m2, "m^2", "Fig. 4.27")
row("total force P", d.total_force_n, "N", "Eq. B.5")
row("force per guest F", d.force_per_guest_n, "N", "Eq. B.6")
row("host-guest effective radius R'", d.host_guest_effective_radius_m, "m", "r_h r_g / (r_h + r_g)")
row("host-guest elastic constant K'", d.host_guest_elastic_constant_pa, "Pa", "Eq. B.3")
row("work of adhesion gamma", d.work_of_adhesion_j_m2, "J/m^2", "Eq. B.9")
row("Hertz contact radius a_h", d.hertz_contact_radius_m, "m", "Eq. B.7")
row("Hertz central displacement", d.hertz_central_displacement_m, "m", "a_h^2 / R'")
row("Hertz central displacement ratio", d.hertz_central_displacement_ratio, "-", "delta / guest diameter")
row("JKR contact radius a_j", d.jkr_contact_radius_m, "m", "Eq. B.8")
row("JKR central displacement", d.jkr_central_displacement_m, "m", "Eq. B.10")
row("JKR central displacement ratio", d.jkr_central_displacement_ratio, "-", "delta / guest diameter")
print(string.format("phi=%.4g a_m=%.4g area=%.4g P=%.4g F=%.4g gamma=%.4g ratio_hertz=%.4g ratio_jkr=%.4g",
  d.limiting_elastic_velocity_m_s, d.max_contact_radius_m, d.contact_area_m2, d.total_force_n,
  d.force_per_guest_n, d.work_of_adhesion_j_m2, d.hertz_central_displacement_ratio, d.jkr_central_displacement_ratio))

if p.collisions ~= "" then
  -- Read the CSV into a list of collision records (header names the columns).
  local file, why = io.open(p.collisions, "r")
  if not file then error("cannot open collisions file: " .. tostring(why)) end
  local header, list, line_number = nil, {}, 0
  for line in file:lines() do
    line_number = line_number + 1
    if line:match("%S") and not line:match("^%s*#") then
      local cells = {}
      for cell in (line .. ","):gmatch("([^,]*),") do cells[#cells + 1] = cell:match("^%s*(.-)%s*$") end
      if not header then
        header = {}
        for k, name in ipairs(cells) do header[name] = k end
        for _, needed in ipairs { "time_s", "max_overlap_m", "effective_radius_m" } do
          if not header[needed] then
            error(string.format("%s: the header has no column '%s'", p.collisions, needed))
          end
        end
      else
        local record = {}
        for _, name in ipairs { "time_s", "max_overlap_m", "effective_radius_m" } do
          local value = tonumber(cells[header[name]])
          if not value then
            error(string.format("%s:%d: column '%s' is not a number", p.collisions, line_number, name))
          end
          record[name] = value
        end
        list[#list + 1] = record
      end
    end
  end
  file:close()
  local time, detail, extra = coating.minimum_time { collisions = list, host_count = p.hosts,
                                                     host_radius_m = p.host_radius,
                                                     patches_per_contact = p.patches_per_contact }
  if time then
    print(string.format("minimum coating time (section 4.7) = %.6g s after %d of %d collisions",
      time, detail.collisions_used, #list))
  else
    print("minimum coating time (section 4.7): not reached; " .. detail)
    print(string.format("covered %.4g of %.4g m^2", extra.covered_area_m2, extra.target_area_m2))
  end
end
