-- agglomerate helper: count zero
-- expect: agglomerate_count_zero\.lua:5\b.*count
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.prepare(sim, { count = 0 })  -- <- wrong
