-- agglomerate helper: unknown option
-- expect: agglomerate_unknown_option\.lua:5\b.*unknown option 'surface_enrgy'
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.prepare(sim, { count = 10, surface_enrgy = 1 })  -- <- wrong
