-- os.exit from a callback in the middle of a run: the program ends with that
-- status, and the output file keeps every series row appended before it (the
-- rows are buffered: os.exit closes the simulations first).
local p = parameters { code = { default = 3 } }
local sim = simulation { dimension = 2 }
sim:material { name = "powder", density = 1200 }
sim:contact { "powder", "powder", model = "linear", k_normal = 1e4, restitution = 0.5 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 5e-3, material = "powder" }
sim:fill { region = { circle = { center = { 0, 0 }, radius = 5e-3 } }, count = 50, radius = 0.3e-3,
           material = "powder", seed = 1, overlap = false }
sim:gravity { 0, -9.81 }
sim:output {}
sim:series("rows", { "time", "kinetic_energy" })
local rows = 0
sim:every { steps = 10, function(s)
  s:append("rows", { s:time(), s:stats().kinetic_energy })
  rows = rows + 1
  if rows == 37 then os.exit(p.code) end
end }
sim:run { steps = 100000 }
