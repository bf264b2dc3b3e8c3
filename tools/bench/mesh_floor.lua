-- What a particle-mesh contact costs beside a particle-plane contact, with equal work:
-- the same bed of spheres (a `per_side`^2 x `layers` lattice of r = 1 mm, Hertz-Mindlin)
-- settles on a floor that is either an analytic plane or a triangle mesh of the same
-- plane cut into `cells`^2 squares (2 `cells`^2 triangles, written here as an ASCII STL).
-- Both runs start from the same state, take the same steps and see the same contacts
-- (checked: the wall-contact counts must agree); they alternate `rounds` times so
-- that a change of machine load falls on both. Prints each run's time and the extra
-- cost of one mesh contact over one plane contact, per contact-step.
--   build/granule run tools/bench/mesh_floor.lua -q
--   build/granule run tools/bench/mesh_floor.lua -q -D cells=300   # 180 000 triangles
local p = parameters {
  per_side = { default = 30, unit = "-", doc = "spheres along x and y" },
  layers = { default = 3, unit = "-", doc = "layers of spheres along z" },
  cells = { default = 30, unit = "-", doc = "squares of the mesh floor along x and y" },
  settle = { default = 4000, unit = "-", doc = "steps to settle the bed before timing" },
  steps = { default = 4000, unit = "-", doc = "steps to time, per round" },
  rounds = { default = 3, unit = "-", doc = "plane/mesh alternations" },
  stl = { default = "mesh_floor.stl", doc = "where the mesh floor is written" },
}
local r = 1e-3
local side = 2 * r * p.per_side
local margin = 0.1 * side

-- The floor z = 0 over [-margin, side + margin]^2, normals up.
do
  local f = assert(io.open(p.stl, "w"))
  f:write("solid floor\n")
  local h = (side + 2 * margin) / p.cells
  local function tri(a, b, c)
    f:write("facet normal 0 0 1\n outer loop\n")
    for _, v in ipairs { a, b, c } do f:write(string.format("  vertex %.17g %.17g 0\n", v[1], v[2])) end
    f:write(" endloop\nendfacet\n")
  end
  for i = 0, p.cells - 1 do
    for j = 0, p.cells - 1 do
      local x0, y0 = -margin + i * h, -margin + j * h
      tri({ x0, y0 }, { x0 + h, y0 }, { x0 + h, y0 + h })
      tri({ x0, y0 }, { x0 + h, y0 + h }, { x0, y0 + h })
    end
  end
  f:write("endsolid floor\n")
  f:close()
end

local function scene(floor)
  local sim = simulation { dimension = 3 }
  sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.25 }
  sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
  if floor == "plane" then
    sim:wall_plane { name = "floor", material = "glass", point = { 0, 0, 0 }, normal = { 0, 0, 1 } }
  else
    sim:wall_mesh { name = "floor", file = p.stl, material = "glass" }
  end
  for _, w in ipairs { { "x0", { 0, 0, 0 }, { 1, 0, 0 } }, { "x1", { side, 0, 0 }, { -1, 0, 0 } },
                       { "y0", { 0, 0, 0 }, { 0, 1, 0 } }, { "y1", { 0, side, 0 }, { 0, -1, 0 } } } do
    sim:wall_plane { name = w[1], material = "glass", point = w[2], normal = w[3] }
  end
  sim:gravity { 0, 0, -9.81 }
  for k = 0, p.layers - 1 do
    for j = 0, p.per_side - 1 do
      for i = 0, p.per_side - 1 do
        -- a little below touching in x and y so the side walls hold the bed
        sim:add_particle { position = { (2 * i + 1) * r, (2 * j + 1) * r, (2.02 * k + 1.01) * r },
                           radius = r * (1 - 0.002 * ((i + 2 * j + 3 * k) % 5)), material = "glass" }
      end
    end
  end
  sim:prepare()
  sim:run { steps = p.settle }
  return sim
end

local sims = { plane = scene("plane"), mesh = scene("mesh") }
local spent = { plane = 0, mesh = 0 }
for _ = 1, p.rounds do
  for _, floor in ipairs { "plane", "mesh" } do
    local sim = sims[floor]
    local t0 = wall_time()
    sim:run { steps = p.steps }
    spent[floor] = spent[floor] + wall_time() - t0
  end
end
local n_plane, n_mesh = sims.plane:stats().contacts_wall, sims.mesh:stats().contacts_wall
if math.abs(n_plane - n_mesh) > 0.01 * n_plane then
  error(string.format("mesh_floor: the runs differ (%d wall contacts on the plane, %d on the mesh)",
                      n_plane, n_mesh))
end
-- The floor's contacts: the spheres that overlap z = 0 (the side walls' are the same in both).
local function on_floor(sim)
  local P, n = sim:arrays(), 0
  for i = 1, #P do if P.z[i] < P.radius[i] then n = n + 1 end end
  return n
end
local floor_plane, floor_mesh = on_floor(sims.plane), on_floor(sims.mesh)
print(string.format("mesh_floor: %d spheres, %d triangles, %d floor contacts (plane %d), %d wall contacts (plane %d), %d x %d steps",
                    #sims.plane:arrays(), 2 * p.cells * p.cells, floor_mesh, floor_plane, n_mesh, n_plane,
                    p.rounds, p.steps))
print(string.format("  plane floor %.3f s, mesh floor %.3f s: ratio %.3f; extra per floor contact-step %.1f ns",
                    spent.plane, spent.mesh, spent.mesh / spent.plane,
                    1e9 * (spent.mesh - spent.plane) / (floor_mesh * p.rounds * p.steps)))
