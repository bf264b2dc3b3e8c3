-- sim:wall_mesh from Lua: a file written here is loaded with a scale, a
-- rotation and a translation; a sphere dropped on it lands where the placed
-- mesh is; sim:wall reports the mesh and its reaction; set_wall moves it;
-- bad input is refused with a message that names the problem.
local path = os.tmpname() .. ".stl"
local f = assert(io.open(path, "w"))
-- A square of side 20 (file units: mm) in the x-y plane, two triangles.
f:write("solid s\n")
for _, t in ipairs { { { -10, -10, 0 }, { 10, -10, 0 }, { 10, 10, 0 } },
                     { { -10, -10, 0 }, { 10, 10, 0 }, { -10, 10, 0 } } } do
  f:write(" facet normal 0 0 1\n  outer loop\n")
  for _, v in ipairs(t) do f:write(string.format("   vertex %g %g %g\n", v[1], v[2], v[3])) end
  f:write("  endloop\n endfacet\n")
end
f:write("endsolid s\n")
f:close()

local function scene()
  local sim = simulation { dimension = 3 }
  sim:material { name = "glass", density = 2500 }
  sim:material { name = "steel", density = 0 }
  sim:contact { "glass", "steel", model = "linear", k_normal = 2000, restitution = 0.5, friction = 0.3 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 2000, restitution = 0.5, friction = 0.3 }
  return sim
end

-- Placed: mm to m, tilted 90 degrees about x (the square now stands in the
-- x-z plane, its normal along y), then lifted by 0.05 m: a wall at y = 0.
local sim = scene()
sim:wall_mesh { name = "plate", file = path, material = "steel", scale = 1e-3,
                rotate = { axis = { 1, 0, 0 }, degrees = 90 }, translate = { 0, 0, 0.05 } }
local r = 1e-3
sim:add_particle { position = { 0, 2 * r, 0.05 }, radius = r, material = "glass", velocity = { 0, -0.1, 0 } }
sim:run { duration = 0.05 }
local w = sim:wall("plate")
assert(w.type == "mesh", "type " .. tostring(w.type))
local y = sim:particle(0).position[2]
assert(sim:particle(0).velocity[2] > 0, "the sphere bounced off the plate at y = 0")
assert(y > r, "above the plate: " .. y)
print(string.format("mesh api: bounced to y = %.4g m", y))

-- Resting on it under gravity along -y: the plate carries the weight.
sim:gravity { 0, -9.81, 0 }
sim:run { duration = 0.3 }
local m = sim:particle(0).mass
local resting = sim:particle(0).position[2]
local fy = sim:wall("plate").force[2]
assert(math.abs(fy + m * 9.81) < 1e-3 * m * 9.81, string.format("force %.6g against weight %.6g", fy, m * 9.81))

-- Moved later: set_wall gives it a velocity along y; the sphere is pushed.
sim:set_wall("plate", { velocity = { 0, 0.01, 0 } })
sim:run { duration = 0.1 }
local offset = sim:wall("plate").offset
assert(math.abs(offset[2] - 0.001) < 1e-6, "offset " .. offset[2])
assert(sim:particle(0).position[2] > resting + 0.0009, "pushed along")
sim:set_wall("plate", { angular_velocity = 2 })
assert(sim:wall("plate").angular_velocity == 2)
-- Its axis as added (z by default), read back as a unit vector.
local axis = sim:wall("plate").axis
assert(axis and axis[1] == 0 and axis[2] == 0 and axis[3] == 1, "axis read back")
local tilted = scene()
tilted:wall_mesh { name = "plate", file = path, material = "steel", scale = 1e-3, axis = { 0, 3, 4 } }
axis = tilted:wall("plate").axis
assert(math.abs(axis[2] - 0.6) < 1e-15 and math.abs(axis[3] - 0.8) < 1e-15, "tilted axis normalised")

-- Pictures draw the mesh's edges seen along z: a flat mesh (the s2 plate
-- below lies in z = 0) shows its five edges as lines, and none without walls.
local function lines_in(file)
  local h = assert(io.open(file)); local text = h:read("a"); h:close(); os.remove(file)
  local n = 0
  for _ in text:gmatch("<line") do n = n + 1 end
  return n
end
local flat = scene()
flat:wall_mesh { name = "plate", file = path, material = "steel", scale = 1e-3 }
flat:add_particle { position = { 0, 0, 2 * r }, radius = r, material = "glass" }
local svg = os.tmpname() .. ".svg"
flat:picture { file = svg, legend = false }
local with_walls = lines_in(svg)
flat:picture { file = svg, legend = false, walls = false }
local without = lines_in(svg)
assert(with_walls - without == 5, string.format("%d lines with walls, %d without", with_walls, without))

-- Euler angles (degrees about the fixed x, y, z axes) place it the same way.
local s2 = scene()
s2:wall_mesh { name = "plate", file = path, material = "steel", scale = 1e-3,
               rotate = { x = 90 } }
s2:add_particle { position = { 0, 2 * r, 0 }, radius = r, material = "glass", velocity = { 0, -0.1, 0 } }
s2:run { duration = 0.05 }
assert(s2:particle(0).velocity[2] > 0, "Euler x = 90: the plate stands at y = 0")

-- Refusals, each naming the problem.
local function refused(fn, piece)
  local ok, err = pcall(fn)
  assert(not ok, "accepted: expected an error with '" .. piece .. "'")
  assert(tostring(err):find(piece, 1, true), "error '" .. tostring(err) .. "' lacks '" .. piece .. "'")
end
refused(function() scene():wall_mesh { name = "m", file = "/nonexistent/part.stl", material = "steel" } end,
        "/nonexistent/part.stl")
refused(function() scene():wall_mesh { name = "m", file = path, material = "steel", scale = -1 } end, "scale")
refused(function() scene():wall_mesh { name = "m", file = path, material = "steel", scal = 2 } end,
        "did you mean 'scale'")
refused(function() scene():wall_mesh { name = "m", file = path, material = "steel",
                                       rotate = { axis = { 0, 0, 0 }, degrees = 3 } } end, "axis")
refused(function()
  local flat = simulation { dimension = 2 }
  flat:material { name = "steel", density = 0 }
  flat:wall_mesh { name = "m", file = path, material = "steel" }
end, "polyline")
os.remove(path)
print("mesh api check ok")
