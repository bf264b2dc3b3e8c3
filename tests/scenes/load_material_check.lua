-- sim:load_particles says when the material it loads saved particles into has
-- another density or elasticity than the file recorded (the loaded masses and
-- the saved overlaps' forces are then not the saved state's), and says nothing
-- when they match. The ctest matches the warning on the output.
local function declare(sim, density)
  sim:material { name = "g", density = density, young = 1e8, poisson = 0.3 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5 }
end
local saved = simulation { dimension = 2 }
declare(saved, 2000)
saved:add_particle { position = { 0, 0 }, radius = 1e-3, material = "g" }
saved:output { file = "load_material_check.h5" }
saved:run { steps = 1 }
saved:close()
for _, density in ipairs { 2000, 3000 } do
  local sim = simulation { dimension = 2 }
  declare(sim, density)
  print(string.format("loading %g", density))
  io.stdout:flush()  -- (the warning goes to standard error, at once)
  local ids = sim:load_particles { file = "load_material_check.h5" }
  assert(#ids == 1)
  local mass = sim:particle(ids[1]).mass
  assert(math.abs(mass - density * 4 / 3 * math.pi * 1e-9) < 1e-12 * mass, "mass " .. mass)
  print(string.format("loaded %g", density))
  io.stdout:flush()
end
print("load material check done")
