-- granule.materials: the material properties of the coating analysis
-- (dissertation Table 4.2 and what appendix B needs), as a small library that
-- scripts can extend.
--
--   local materials = require "granule.materials"
--   local pmma = materials.get("PMMA")            -- a copy; change it freely
--   materials.define { name = "PMMA_stiff", base = "PMMA", young_modulus_pa = 6.6e9 }
--   materials.names()                             -- { "Al2O3", "PMMA", "PMMA_stiff" }
--
-- A material is a table with these fields (SI units; names carry the unit):
--   name                             text
--   density_kg_m3                    rho of Table 4.2
--   young_modulus_pa                 E
--   poisson_ratio                    nu
--   surface_energy_dispersive_j_m2   omega_d of Table 4.2 and Eq. B.9
--   surface_energy_polar_j_m2        omega_p of Table 4.2 and Eq. B.9
--   yield_stress_pa                  Y of Eqs. B.1, B.2, B.5 (optional: only the
--                                    impacting host particle needs it)
--   source                           where the numbers come from
local checks = require "granule.checks"

local M = {}

local fields = {
  "name", "base", "density_kg_m3", "young_modulus_pa", "poisson_ratio",
  "surface_energy_dispersive_j_m2", "surface_energy_polar_j_m2", "yield_stress_pa", "source",
}

local library = {}

local function copy(t)
  local c = {}
  for k, v in pairs(t) do c[k] = v end
  return c
end

local function sorted_names()
  local names = {}
  for name in pairs(library) do names[#names + 1] = name end
  table.sort(names)
  return names
end

-- Validates a complete material; `where` names the public function for messages.
local function validate(where, m)
  if type(m.name) ~= "string" or m.name == "" then checks.fail(where, "name", "a non-empty string", m.name) end
  checks.positive(where, "density_kg_m3", m.density_kg_m3, "kg/m^3")
  checks.positive(where, "young_modulus_pa", m.young_modulus_pa, "Pa")
  -- nu = 0.5 (incompressible) is what Table 4.2 gives PMMA; above it, or at -1
  -- and below, the elastic constants of Eq. B.3 lose their meaning.
  checks.half_open(where, "poisson_ratio", m.poisson_ratio, -1, 0.5)
  checks.non_negative(where, "surface_energy_dispersive_j_m2", m.surface_energy_dispersive_j_m2, "J/m^2")
  checks.non_negative(where, "surface_energy_polar_j_m2", m.surface_energy_polar_j_m2, "J/m^2")
  if m.yield_stress_pa ~= nil then checks.positive(where, "yield_stress_pa", m.yield_stress_pa, "Pa") end
  return m
end

--- materials.define { name = ..., [base = "PMMA"], field = value, ... } -> material
--- Adds a material, or replaces one of the same name. With `base`, the fields
--- not given are copied from that material (so an override names only what
--- changes). Every field is checked; a bad or unknown field is an error that
--- names it. Returns a copy of the stored material.
function M.define(spec)
  local where = "materials.define"
  checks.table_arg(where, spec, "name = ..., base = ..., density_kg_m3 = ..., ...")
  checks.known_keys(where, spec, fields)
  local m = {}
  if spec.base ~= nil then m = M.get(spec.base) end
  for k, v in pairs(spec) do
    if k ~= "base" then m[k] = v end
  end
  if spec.base ~= nil and spec.source == nil then
    m.source = string.format("%s, modified by a script", spec.base)
  end
  validate(where, m)
  library[m.name] = m
  return copy(m)
end

--- materials.get(name, [context]) -> a copy of the material called `name`.
--- Names are matched exactly; an unknown name is an error that suggests the
--- nearest known name. Passing a material table returns a checked copy of it,
--- so functions can take either a name or a table. `context` (e.g.
--- "coating.host_host_impact: 'host'") starts the error messages.
function M.get(name_or_material, context)
  local where = context or "materials.get"
  if type(name_or_material) == "table" then
    checks.known_keys(where, name_or_material, fields)
    return validate(where, copy(name_or_material))
  end
  if type(name_or_material) ~= "string" then
    checks.fail(where, "name", "a material name or a material table", name_or_material)
  end
  local m = library[name_or_material]
  if not m then
    local names = sorted_names()
    local hint = checks.nearest(name_or_material, names)
    checks.raise(string.format("%s: unknown material '%s'%s; known: %s", where, name_or_material,
      hint and string.format(" (did you mean '%s'?)", hint) or "", table.concat(names, ", ")))
  end
  return copy(m)
end

--- materials.names() -> sorted list of the defined material names.
function M.names()
  return sorted_names()
end

--- materials.describe(name) -> one readable line per field.
function M.describe(name_or_material)
  local m = M.get(name_or_material)
  local lines = { m.name }
  for _, k in ipairs(fields) do
    if k ~= "name" and k ~= "base" and m[k] ~= nil then
      local v = m[k]
      lines[#lines + 1] = string.format("  %-32s %s", k, type(v) == "number" and string.format("%.6g", v) or tostring(v))
    end
  end
  return table.concat(lines, "\n")
end

-- Table 4.2 of the dissertation (host PMMA 400 um, guest Al2O3 5 um).
M.define {
  name = "PMMA",
  density_kg_m3 = 1190,
  young_modulus_pa = 3300e6,
  poisson_ratio = 0.5,
  surface_energy_dispersive_j_m2 = 35.9e-3,
  surface_energy_polar_j_m2 = 4.3e-3,
  -- The dissertation lists no yield stress. Appendix B states phi = 0.0081 m/s
  -- from Eq. B.1 with this material's E and nu; Y = 15 MPa (a round number)
  -- gives 0.00815 m/s, so we take it as the value the author used. Bulk PMMA's
  -- compressive yield stress is nearer 100 MPa, which would give phi = 0.9 m/s:
  -- override with materials.define { name = "PMMA", base = "PMMA", yield_stress_pa = ... }.
  yield_stress_pa = 15e6,
  source = "Table 4.2; Y inferred from appendix B's phi = 0.0081 m/s (Eq. B.1)",
}

M.define {
  name = "Al2O3",
  density_kg_m3 = 3970,
  young_modulus_pa = 345e9,
  poisson_ratio = 0.26,
  surface_energy_dispersive_j_m2 = 1000e-3,
  surface_energy_polar_j_m2 = 540e-3,
  -- The guest is treated as rigid in appendix B (only its E and nu enter K' of
  -- Eq. B.7 through B.3), so no yield stress is needed.
  source = "Table 4.2",
}

return M
