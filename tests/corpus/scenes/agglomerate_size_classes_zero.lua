-- agglomerate helper: size classes zero
-- expect: agglomerate_size_classes_zero\.lua:5\b.*size_classes
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.size_classes(5e-6, 0.05, 0)  -- <- wrong
