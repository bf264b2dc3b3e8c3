-- A small 3D scene for the output tests: a drum along z, a cylinder lying along
-- x, a floor that moves (so the XDMF walls change with time), snapshots, and a
-- picture of each colouring. Every check can fail.
local sim = simulation { dimension = 3 }
sim:material { name = "glass", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:contact { "glass", "steel", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0, 0 }, radius = 0.01, material = "steel" }
sim:wall_cylinder { name = "rod", center = { 0, 0.006, 0.004 }, axis = { 1, 0, 0 }, radius = 1e-3,
                    inside = false, material = "steel" }
sim:wall_plane { name = "floor", point = { 0, -0.008, 0 }, normal = { 0, 1, 0 }, material = "steel" }
sim:fill { region = { box = { lo = { -0.006, -0.007, -0.002 }, hi = { 0.006, 0.003, 0.002 } } },
           count = 40, radius = 5e-4, material = "glass", seed = 4, max_speed = 0.05, overlap = false }
sim:add_particle { position = { 0.007, 0, 0 }, radius = 5e-4, material = "steel", fixed = true }
sim:gravity { 0, -9.81, 0 }
local file = sim:output { file = "output_3d_test.h5", snapshot_every = 0.01 }
sim:set_wall("floor", { velocity = { 0, 0.01, 0 } })
sim:run { duration = 0.03 }
for _, colour in ipairs { "speed", "material", "fixed", "radius", "spin" } do
  local png = sim:picture { file = "output_3d_" .. colour .. ".png", width = 240, color_by = colour }
  local f = assert(io.open(png, "rb"))
  assert(f:read(8) == "\137PNG\r\n\26\n", png .. " is not a PNG")
  f:close()
end
sim:picture { file = "output_3d.svg", view = { lo = { -0.012, -0.012 }, hi = { 0.012, 0.012 } } }
sim:close()
print("output_3d ok: " .. file)
