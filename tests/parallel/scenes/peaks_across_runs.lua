-- A contact going on when one sim:run ends and the next begins keeps its
-- beginning and its peaks (contact_peaks, overlaps, areas), spread over ranks
-- as on one process: a head-on pair in a chamber, the run split after the peak
-- force, while the spheres still touch. Prints the diagnostics' results.
local p = parameters { split = { default = 0, integer = true, min = 0, max = 199 } }
local sim = simulation { dimension = 2, steps_per_contact = 40 }
sim:set { canonical_order = true }
sim:material { name = "g", density = 2500 }
sim:contact { "g", "g", model = "walton_braun", k_load = 2e4, restitution = 0.9, friction = 0.3 }
sim:wall_cylinder { name = "chamber", center = { 0, 0 }, radius = 10e-3, material = "g" }
sim:wall_cylinder { name = "inner_piece", center = { -8e-3, 0 }, radius = 0.5e-3, inside = false,
                    material = "g" }
sim:add_particle { position = { 0, 0 }, radius = 1e-3, material = "g", velocity = { 0.5, 0 } }
sim:add_particle { position = { 2.01e-3, 0 }, radius = 1e-3, material = "g", velocity = { -0.5, 0 } }
local peaks = sim:diagnostic("contact_peaks", { window = 1 })
local overlaps = sim:diagnostic("overlaps", { every = 100000, window = 1 })
local areas = sim:diagnostic("areas", { every = 1, window = 1 })
if p.split > 0 then
  sim:run { steps = p.split }
  sim:run { steps = 200 - p.split }
else
  sim:run { steps = 200 }
end
for _, id in ipairs { peaks, overlaps, areas } do
  local r = sim:diagnostic_results(id)
  local keys = {}
  for k, v in pairs(r) do if type(v) == "number" then keys[#keys + 1] = k end end
  table.sort(keys)
  for _, k in ipairs(keys) do print(string.format("%s %.17g", k, r[k])) end
end
