-- granule.materials: Table 4.2, extension from scripts, and errors that name
-- what is wrong. Every assertion can fail.
local H = dofile(SCENE_PATH:match("^(.*)[/\\]") .. "/helpers.lua")
local materials = require "granule.materials"

-- Table 4.2 as printed (SI units).
local table_4_2 = {
  PMMA = { density_kg_m3 = 1190, young_modulus_pa = 3300e6, poisson_ratio = 0.5,
           surface_energy_dispersive_j_m2 = 35.9e-3, surface_energy_polar_j_m2 = 4.3e-3 },
  Al2O3 = { density_kg_m3 = 3970, young_modulus_pa = 345e9, poisson_ratio = 0.26,
            surface_energy_dispersive_j_m2 = 1000e-3, surface_energy_polar_j_m2 = 540e-3 },
}
for name, expected in pairs(table_4_2) do
  local m = materials.get(name)
  H.check(m.name == name, "name of " .. name)
  for field, value in pairs(expected) do
    H.relative(m[field], value, 1e-12, string.format("Table 4.2 %s %s", name, field))
  end
end
H.check(materials.get("PMMA").yield_stress_pa > 0, "PMMA carries the yield stress appendix B needs")

-- get() returns copies: changing one does not change the library.
local copy = materials.get("PMMA")
copy.young_modulus_pa = 1
H.check(materials.get("PMMA").young_modulus_pa == 3300e6, "materials.get must return a copy")

-- define(): new materials, overrides of some fields from a base, replacement.
local glass = materials.define { name = "glass", density_kg_m3 = 2500, young_modulus_pa = 63e9, poisson_ratio = 0.23,
                                 surface_energy_dispersive_j_m2 = 0.03, surface_energy_polar_j_m2 = 0.02 }
H.check(glass.name == "glass" and materials.get("glass").density_kg_m3 == 2500, "a new material is stored")
local stiff = materials.define { name = "PMMA_stiff", base = "PMMA", young_modulus_pa = 6.6e9 }
H.check(stiff.young_modulus_pa == 6.6e9 and stiff.density_kg_m3 == 1190, "override keeps the base's other fields")
H.check(materials.get("PMMA").young_modulus_pa == 3300e6, "the base is unchanged")
local names = table.concat(materials.names(), ",")
H.check(names:find("PMMA_stiff", 1, true) and names:find("glass", 1, true), "names() lists new materials: " .. names)
materials.define { name = "glass", base = "glass", density_kg_m3 = 2600 }
H.check(materials.get("glass").density_kg_m3 == 2600, "define replaces a material of the same name")

-- Unknown names suggest the nearest one; the error points at this file.
local call_line
local message = H.fails("did you mean 'PMMA'", function()
  call_line = debug.getinfo(1, "l").currentline local m = materials.get("PMAA")  -- the error must point here
  return m
end)
H.check(message:find("test_materials.lua:" .. call_line .. ":", 1, true),
  "the error is located in the caller, not in the library: " .. message)
H.fails("did you mean 'Al2O3'", materials.get, "al2o3")
H.fails("unknown material 'unobtainium'", materials.get, "unobtainium")
-- Bad fields name themselves.
H.fails("density_kg_m3", materials.define, { name = "bad", base = "PMMA", density_kg_m3 = -1 })
H.fails("young_modulus_pa", materials.define, { name = "bad", base = "PMMA", young_modulus_pa = 0 / 0 })
H.fails("poisson_ratio", materials.define, { name = "bad", base = "PMMA", poisson_ratio = 0.7 })
H.fails("did you mean 'young_modulus_pa'", materials.define, { name = "bad", base = "PMMA", youngs_modulus_pa = 1e9 })
H.fails("surface_energy_polar_j_m2", materials.define, { name = "bad", density_kg_m3 = 1, young_modulus_pa = 1,
  poisson_ratio = 0.3, surface_energy_dispersive_j_m2 = 0 })
H.check(not pcall(materials.get, "bad"), "a refused material is not stored")

print("analysis.materials ok")
