-- A scene that writes one file, finishes it by opening a second, and then fails:
-- the first is named complete, the second partial (tests/CMakeLists.txt).
local sim = simulation { dimension = 3, time_step = 1e-5 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.9 }
sim:add_particle { position = { 0, 0, 0 }, radius = 1e-3, material = "glass" }
sim:output { file = "two_outputs_first.h5" }
sim:run { steps = 10 }
sim:output { file = "two_outputs_second.h5" }
sim:run { steps = 10 }
error("the scene fails after its second output")
