-- The preparation protocol (dissertation 7.3) on a small agglomerate of 60
-- primaries: every stage must end on its criterion, not its cap; the result
-- must be at rest, bonded into one piece with about as many tensile as
-- compressive contacts, and stay so through a long quiet run with neither the
-- field nor the damping. Writes the agglomerate for the wall-impact checks
-- (-o agglomerate_test.h5). Every assertion can fail.
local agglomerate = require "granule.agglomerate"

local count, rest_speed = 60, 1e-4
local sim = simulation { dimension = 2, record_contacts = true }
local out = sim:output {}
local report = agglomerate.prepare(sim, { count = count, generation_diameter = 52e-6, rest_speed = rest_speed,
                                          quiet_duration = 100e-6, quiet = true })
agglomerate.write_preparation(sim, report)
print(agglomerate.preparation_line(report))

for k, stage in ipairs(report.stages) do
  assert(stage.ended_by == "criterion", string.format("stage %d (%s) ended by its cap", k, stage.name))
end
-- At rest: after the quiet run the internal rms speed is still of the order of
-- the rest criterion (a loaded spring would ring at ~1e-2 m/s).
assert(report.rms_speed < 3 * rest_speed, "not at rest: rms speed " .. report.rms_speed .. " m/s")
assert(report.quiet.peak_rms_speed < 3 * rest_speed,
  "the quiet run moved: peak rms speed " .. report.quiet.peak_rms_speed .. " m/s")
-- Held together: every bond kept, one fragment, a connected 2D packing.
assert(report.quiet.bonds_before == report.quiet.bonds_after,
  string.format("bonds lost in the quiet run: %d -> %d", report.quiet.bonds_before, report.quiet.bonds_after))
local f = sim:fragments { material = "alumina" }
assert(f.count == 1, "the agglomerate fell apart into " .. f.count .. " fragments")
assert(report.coordination > 3 and report.coordination < 4.5, "coordination number " .. report.coordination)
-- 7.3: "the number of compressive contact forces approximately equal to the
-- number of tensile contact forces".
local ratio = report.tensile / report.compressive
assert(ratio > 0.6 and ratio < 1.7, string.format("tensile / compressive = %d / %d", report.tensile, report.compressive))
-- Dense: the diameter of 60 discs of 5 um at a packing fraction 0.7-0.85.
local solid = count * 2.5e-6 ^ 2
local fraction = solid / (report.diameter / 2) ^ 2
assert(fraction > 0.6 and fraction < 0.9, "packing fraction " .. fraction)

-- The coordination the report gives (from the engine's contact list), counted
-- again from the positions alone: the pairs whose discs overlap. A JKR bond
-- can last to a small negative overlap (alpha_f, 6.3.3), but at rest under zero
-- load every bond sits near its equilibrium overlap, which is positive.
local function overlapping_pairs(s, ids)
  local p = {}
  for k, id in ipairs(ids) do p[k] = s:particle(id) end
  local n = 0
  for a = 1, #p do
    for b = a + 1, #p do
      local dx, dy = p[a].position[1] - p[b].position[1], p[a].position[2] - p[b].position[2]
      if math.sqrt(dx * dx + dy * dy) < p[a].radius + p[b].radius then n = n + 1 end
    end
  end
  return n
end
local counted = overlapping_pairs(sim, report.ids)
assert(counted == report.bonds, string.format("the report says %d bonds, the positions overlap in %d pairs",
  report.bonds, counted))
assert(math.abs(report.coordination - 2 * counted / count) < 1e-12, "coordination " .. report.coordination)
agglomerate.save(sim, out, report)

-- The sticky protocol (friction and adhesion on while compacting, at the
-- agglomerate's friction and surface energy) ends at rest too, with fewer
-- bonds than the dense one, counted the same way.
local sticky_sim = simulation { dimension = 2, record_contacts = true }
local sticky = agglomerate.prepare(sticky_sim, { protocol = "sticky", count = count, generation_diameter = 52e-6,
                                                 rest_speed = rest_speed, friction = 0.3, quiet = true })
print("sticky: " .. agglomerate.preparation_line(sticky))
assert(sticky.options.compaction_friction == 0.3 and sticky.stages[1].name:find("mu = 0.3", 1, true),
  "sticky compacted at mu = " .. tostring(sticky.options.compaction_friction) .. " (" .. sticky.stages[1].name .. ")")
for k, stage in ipairs(sticky.stages) do
  assert(stage.ended_by == "criterion", string.format("sticky stage %d (%s) ended by its cap", k, stage.name))
end
assert(sticky.rms_speed < 3 * rest_speed, "sticky: not at rest: rms speed " .. sticky.rms_speed .. " m/s")
local sticky_counted = overlapping_pairs(sticky_sim, sticky.ids)
assert(sticky_counted == sticky.bonds, string.format("sticky: the report says %d bonds, the positions overlap in %d",
  sticky.bonds, sticky_counted))
assert(sticky.bonds < report.bonds, string.format("sticky: %d bonds, not fewer than the dense %d", sticky.bonds,
  report.bonds))
-- Stage 3 as a ramp (decrement_duration): it ends at its fixed time, which is
-- not the rest criterion and is not reported as it.
local ramp = agglomerate.prepare(simulation { dimension = 2, record_contacts = true },
  { count = count, generation_diameter = 52e-6, rest_speed = rest_speed, decrement_duration = 0.5e-6, quiet = true })
assert(ramp.stages[3].ended_by == "duration" and ramp.stages[1].ended_by == "criterion",
  "a ramp's stage 3 ended by " .. ramp.stages[3].ended_by)
print("agglomerate_prepare_check ok")
