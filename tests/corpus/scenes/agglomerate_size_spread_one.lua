-- agglomerate helper: size spread one
-- expect: agglomerate_size_spread_one\.lua:5\b.*size_spread
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.size_classes(5e-6, 1, 7)  -- <- wrong
