-- granule.mesh_shapes: simple shapes written as OBJ files for sim:wall_mesh, for
-- scenes that build their equipment from triangles (a drum's shell, an inner
-- piece, a blade) without a CAD file. Coordinates in metres.
--
--   local shapes = require "granule.mesh_shapes"
--   local path = shapes.prism { center = { 0, 0 }, radius = 15e-3, facets = 96, z_min = 0, z_max = 8e-3 }
--   sim:wall_mesh { name = "drum", file = path, material = "steel" }
--   os.remove(path)

local shapes = {}

local function finite(x) return type(x) == "number" and x == x and x ~= math.huge and x ~= -math.huge end
local function need(ok, where, what) if not ok then error(where .. ": " .. what, 3) end end

-- A fresh file name for a shape (os.tmpname creates the file; the OBJ replaces it).
local function temp_path(kind)
  local base = os.tmpname()
  os.remove(base)
  return base .. "_" .. kind .. ".obj"
end

local function write(path, vertices, faces)
  local f = assert(io.open(path, "w"))
  for _, v in ipairs(vertices) do f:write(string.format("v %.17g %.17g %.17g\n", v[1], v[2], v[3])) end
  for _, t in ipairs(faces) do f:write(string.format("f %d %d %d\n", t[1], t[2], t[3])) end
  f:close()
  return path
end

--- shapes.prism { center = { x, y }, radius =, facets =, z_min =, z_max = [, file = ] } -> path
--- The side of a right prism along z whose `facets` flat faces (two triangles
--- each) have their edges on the circle of `radius` about `center`: a polygon
--- inscribed in the circle, R (1 - cos(pi / facets)) inside it at each face's
--- middle. Open at both ends. Returns the OBJ file's path (a temporary file
--- unless `file` is given).
function shapes.prism(o)
  local where = "mesh_shapes.prism"
  need(type(o) == "table", where, "expects a table")
  need(type(o.center) == "table" and finite(o.center[1]) and finite(o.center[2]), where, "center must be { x, y }")
  need(finite(o.radius) and o.radius > 0, where, "radius must be a number > 0 (m)")
  need(math.type(o.facets) == "integer" and o.facets >= 3, where, "facets must be an integer >= 3")
  need(finite(o.z_min) and finite(o.z_max) and o.z_max > o.z_min, where, "z_min < z_max (m)")
  local vertices, faces = {}, {}
  for k = 0, o.facets - 1 do
    local a = 2 * math.pi * k / o.facets
    local x, y = o.center[1] + o.radius * math.cos(a), o.center[2] + o.radius * math.sin(a)
    vertices[#vertices + 1] = { x, y, o.z_min }
    vertices[#vertices + 1] = { x, y, o.z_max }
  end
  for k = 0, o.facets - 1 do
    local a0, a1 = 2 * k + 1, 2 * ((k + 1) % o.facets) + 1  -- OBJ indices from 1
    faces[#faces + 1] = { a0, a1, a1 + 1 }
    faces[#faces + 1] = { a0, a1 + 1, a0 + 1 }
  end
  return write(o.file or temp_path("prism"), vertices, faces)
end

--- shapes.box { corner = { x, y, z }, edges = { a, b, c } [, file = ] } -> path
--- A closed parallelepiped (12 triangles): the corner and its three edge
--- vectors (m), which must not lie in one plane.
function shapes.box(o)
  local where = "mesh_shapes.box"
  need(type(o) == "table", where, "expects a table")
  local function vec3(v) return type(v) == "table" and finite(v[1]) and finite(v[2]) and finite(v[3]) end
  need(vec3(o.corner), where, "corner must be { x, y, z }")
  need(type(o.edges) == "table" and vec3(o.edges[1]) and vec3(o.edges[2]) and vec3(o.edges[3]), where,
    "edges must be three vectors { x, y, z }")
  local a, b, c = o.edges[1], o.edges[2], o.edges[3]
  local volume = a[1] * (b[2] * c[3] - b[3] * c[2]) - a[2] * (b[1] * c[3] - b[3] * c[1]) + a[3] * (b[1] * c[2] - b[2] * c[1])
  local scale = math.sqrt((a[1] ^ 2 + a[2] ^ 2 + a[3] ^ 2) * (b[1] ^ 2 + b[2] ^ 2 + b[3] ^ 2) * (c[1] ^ 2 + c[2] ^ 2 + c[3] ^ 2))
  need(math.abs(volume) > 1e-12 * scale, where, "the three edges lie in one plane")
  local vertices = {}
  for k = 0, 7 do  -- bit 0: +a, bit 1: +b, bit 2: +c
    local v = { o.corner[1], o.corner[2], o.corner[3] }
    for d, e in ipairs { a, b, c } do
      if (k >> (d - 1)) & 1 == 1 then for i = 1, 3 do v[i] = v[i] + e[i] end end
    end
    vertices[k + 1] = v
  end
  -- Each face as two triangles (orientation does not matter: walls are two-sided).
  local quads = { { 0, 1, 3, 2 }, { 4, 5, 7, 6 }, { 0, 1, 5, 4 }, { 2, 3, 7, 6 }, { 0, 2, 6, 4 }, { 1, 3, 7, 5 } }
  local faces = {}
  for _, q in ipairs(quads) do
    faces[#faces + 1] = { q[1] + 1, q[2] + 1, q[3] + 1 }
    faces[#faces + 1] = { q[1] + 1, q[3] + 1, q[4] + 1 }
  end
  return write(o.file or temp_path("box"), vertices, faces)
end

--- shapes.vertices(path) -> { { x, y, z }, ... }
--- The vertices of a mesh file as sim:wall_mesh reads it (STL binary or
--- ASCII, OBJ), one entry per triangle corner for an STL, in the file's
--- units: for a scene to check that a CAD file is the geometry its
--- parameters describe.
function shapes.vertices(path)
  local where = "mesh_shapes.vertices"
  need(type(path) == "string", where, "path must be a string")
  local f, err = io.open(path, "rb")
  need(f, where, "cannot open '" .. path .. "': " .. tostring(err))
  local data = f:read("a")
  f:close()
  local vertices = {}
  -- A binary STL: an 80-byte header, a count n, then n records of 50 bytes
  -- (normal, three corners as little-endian floats, an attribute word).
  if #data >= 84 then
    local n = string.unpack("<I4", data, 81)
    if #data == 84 + 50 * n then
      for t = 0, n - 1 do
        local at = 84 + 50 * t + 12 + 1
        for corner = 0, 2 do
          local x, y, z = string.unpack("<fff", data, at + 12 * corner)
          vertices[#vertices + 1] = { x, y, z }
        end
      end
      return vertices
    end
  end
  local number = "([-+]?[%d%.]+[eE]?[-+]?%d*)"
  local stl = "^%s*vertex%s+" .. number .. "%s+" .. number .. "%s+" .. number
  local obj = "^%s*v%s+" .. number .. "%s+" .. number .. "%s+" .. number
  for line in data:gmatch("[^\r\n]+") do
    local x, y, z = line:match(stl)
    if not x then x, y, z = line:match(obj) end
    if x then vertices[#vertices + 1] = { tonumber(x), tonumber(y), tonumber(z) } end
  end
  need(#vertices > 0, where, "no vertices in '" .. path .. "' (STL binary or ASCII, OBJ)")
  return vertices
end

return shapes
