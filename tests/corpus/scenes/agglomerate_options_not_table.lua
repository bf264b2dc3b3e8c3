-- agglomerate helper: options not table
-- expect: agglomerate_options_not_table\.lua:5\b.*(option|table)
local agglomerate = require "granule.agglomerate"
local sim = simulation { dimension = 2, record_contacts = true }
agglomerate.prepare(sim, "small")  -- <- wrong
