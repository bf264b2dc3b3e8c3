-- agglomerate helper: density nan
-- expect: agglomerate_density_nan\.lua:5\b.*density
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.prepare(sim, { count = 10, density = 0/0 })  -- <- wrong
