-- agglomerate helper: seed fraction
-- expect: agglomerate_seed_fraction\.lua:5\b.*seed
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.prepare(sim, { count = 10, seed = 1.5 })  -- <- wrong
