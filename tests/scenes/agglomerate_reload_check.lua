-- A prepared agglomerate reloaded with its contact histories (the file written
-- by agglomerate_prepare_check.lua: a snapshot and the histories of the same
-- step) is the prepared state: left alone for 20 us, with neither field nor
-- damping, it keeps every bond, its internal rms speed stays at the prepared
-- level (below 3 x the 1e-4 m/s rest criterion of 7.3) and no primary moves by
-- more than 1 nm. The same file reloaded without the histories starts with the
-- tangential forces at zero and rings (the check that the first half can fail:
-- it must move at least ten times faster). Every assertion can fail.
local agglomerate = require "granule.agglomerate"

local rest_speed, quiet = 1e-4, 20e-6

local function reload(histories)
  local sim = simulation { dimension = 2, record_contacts = true }
  local a = agglomerate.alumina
  sim:material { name = "alumina", density = a.density, young = a.young, poisson = a.poisson }
  sim:contact { "alumina", "alumina", model = "thornton_jkr", friction = a.friction, surface_energy = 1.0 }
  local ids, restored = sim:load_particles { file = "agglomerate_test.h5", histories = histories }
  local mass = agglomerate.total_mass(sim, ids)
  local start = {}
  for _, id in ipairs(ids) do start[id] = sim:particle(id).position end
  sim:run { steps = 1 }
  local bonds = #sim:bonds { material = "alumina" }
  local peak = 0
  sim:every { steps = 100, function(s) peak = math.max(peak, agglomerate.internal_rms_speed(s:stats(), mass)) end }
  sim:run { duration = quiet }
  local moved = 0
  for _, id in ipairs(ids) do
    local x = sim:particle(id).position
    moved = math.max(moved, math.sqrt((x[1] - start[id][1]) ^ 2 + (x[2] - start[id][2]) ^ 2))
  end
  local r = { restored = restored, bonds_loaded = bonds, bonds_after = #sim:bonds { material = "alumina" },
              peak = peak, moved = moved }
  print(string.format("histories=%s restored=%d bonds=%d->%d peak_rms_speed_m_s=%.3g max_displacement_m=%.3g",
    tostring(histories), r.restored, r.bonds_loaded, r.bonds_after, r.peak, r.moved))
  return r
end

local kept = reload(true)
assert(kept.restored >= kept.bonds_loaded and kept.bonds_loaded > 0,
  string.format("%d histories restored for %d bonds", kept.restored, kept.bonds_loaded))
assert(kept.bonds_after == kept.bonds_loaded,
  string.format("bonds lost when left alone: %d -> %d", kept.bonds_loaded, kept.bonds_after))
assert(kept.peak < 3 * rest_speed, "the reloaded agglomerate moved: peak rms speed " .. kept.peak .. " m/s")
assert(kept.moved < 1e-9, "a primary moved by " .. kept.moved .. " m")

local lost = reload(false)
assert(lost.restored == 0, "histories = false restored " .. lost.restored)
assert(lost.peak > 10 * kept.peak, string.format("without histories the agglomerate does not ring (%g m/s against %g)",
  lost.peak, kept.peak))
print("agglomerate_reload_check ok")
