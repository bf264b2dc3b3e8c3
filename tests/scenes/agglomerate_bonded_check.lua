-- Wall impacts (dissertation 7.6) of the small agglomerate written by
-- agglomerate_prepare_check.lua, held by parallel bonds instead of adhesion
-- (tests.run's `bonds`): every pair that touched is bonded and nothing else
-- holds it; a very slow impact breaks no bond (the dilated packing is
-- force-free), a 0.2 m/s impact breaks some and not all, and a faster impact
-- breaks more than a slower one. Every assertion can fail.
local tests = require "granule.agglomerate_tests"

local function wall_impact(velocity, name)
  local sim = simulation { dimension = 2, record_contacts = true }
  sim:output { file = name }
  local r = tests.run(sim, "wall", { file = "agglomerate_test.h5", velocity = velocity, bonds = {}, quiet = true })
  print(tests.summary_line(r))
  assert(r.ended_by == "criterion", name .. ": ended by its cap")
  assert(r.contact_start >= 0 and r.impact_duration > 0, name .. ": the agglomerate never reached the wall")
  assert(r.bonded == 1 and r.parallel_bonds > 0, name .. ": no parallel bonds made")
  -- One bond per pair that overlapped in the loaded packing, no more, no fewer.
  assert(r.parallel_bonds == r.pairs_touching,
    string.format("%s: %d bonds for %d touching pairs", name, r.parallel_bonds, r.pairs_touching))
  assert(r.dilation > 0 and r.dilation < 1e-3, name .. ": dilation " .. r.dilation)
  -- Damage is the broken parallel bonds over those made, and both agree with the engine's count.
  local c = sim:bond_counts()
  assert(c.broken == r.parallel_bonds_broken and c.intact + c.broken == r.parallel_bonds,
    string.format("%s: sim:bond_counts %d intact %d broken, the breakage %d of %d", name, c.intact, c.broken,
      r.parallel_bonds_broken, r.parallel_bonds))
  assert(r.damage_ratio == r.parallel_bonds_broken / r.parallel_bonds, name .. ": damage ratio " .. r.damage_ratio)
  -- Fragments are the clusters of the intact bonds: no broken bond, one piece.
  assert((r.parallel_bonds_broken == 0) == (r.fragments == 1),
    string.format("%s: %d bonds broken, %d fragments", name, r.parallel_bonds_broken, r.fragments))
  sim:close()
  return r
end

local slow = wall_impact(0.005, "agglomerate_bonded_slow.h5")
assert(slow.parallel_bonds_broken == 0 and slow.debris_ratio == 0,
  string.format("a 5 mm/s impact broke %d bonds, debris ratio %g", slow.parallel_bonds_broken, slow.debris_ratio))

local gentle = wall_impact(0.1, "agglomerate_bonded_0.1.h5")
local hard = wall_impact(0.2, "agglomerate_bonded_0.2.h5")
assert(hard.parallel_damage_ratio > 0 and hard.parallel_damage_ratio < 1,
  "a 0.2 m/s impact: parallel damage ratio " .. hard.parallel_damage_ratio .. ", not in (0, 1)")
assert(hard.parallel_bonds_broken > gentle.parallel_bonds_broken,
  string.format("0.2 m/s broke %d bonds, no more than 0.1 m/s (%d)", hard.parallel_bonds_broken,
    gentle.parallel_bonds_broken))
assert(hard.debris_ratio > gentle.debris_ratio,
  string.format("0.2 m/s made no more debris (%g) than 0.1 m/s (%g)", hard.debris_ratio, gentle.debris_ratio))
print("agglomerate_bonded_check ok")
