-- agglomerate helper: region too small
-- expect: agglomerate_region_too_small\.lua:5\b.*(generation_diameter|small)
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.random_positions(2, { 0, 0 }, 1e-6, { 1e-6, 1e-6, 1e-6, 1e-6, 1e-6 }, 0)  -- <- wrong
