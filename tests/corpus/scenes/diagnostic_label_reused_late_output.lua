-- a label back with other options, the output opened after the first
-- expect: diagnostic_label_reused_late_output\.lua:13\b.*label 'zones' was used in this output by a removed diagnostic with other options
local sim = simulation { dimension = 2 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 0 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 5, radius = 3e-4, material = "glass", seed = 2 }
local first = sim:diagnostic("zones", {})
sim:output {}
sim:remove_diagnostic(first)
sim:diagnostic("zones", { mean = "cartesian" })  -- <- wrong
sim:run { steps = 10 }
