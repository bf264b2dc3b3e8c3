-- sim:wall_polyline from Lua (2D): a disk dropped into a V whose floor is an
-- arc comes to rest on it; sim:wall reports the polyline and its reaction;
-- set_wall moves it; describe, pictures and the XDMF walls file show it;
-- bad input is refused with a message that names the parameter.
local function scene(dimension)
  local sim = simulation { dimension = dimension or 2, record_contacts = true }
  sim:material { name = "glass", density = 2500 }
  sim:material { name = "steel", density = 0 }
  sim:contact { "glass", "steel", model = "linear", k_normal = 2000, restitution = 0.5, friction = 0.3 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 2000, restitution = 0.5, friction = 0.3 }
  return sim
end

-- A V of two straight sides with a rounded bottom: segment 2 an arc of
-- radius 5 mm bulging down (to the right of its direction, +x).
local sim = scene()
sim:gravity { 0, -9.81 }
sim:wall_polyline { name = "cup", material = "steel",
                    points = { { -0.01, 0.01 }, { -0.002, 0.001 }, { 0.002, 0.001 }, { 0.01, 0.01 } },
                    arcs = { { segment = 2, radius = -0.005 } } }
local r = 1e-3
-- Dropped onto the arc's lowest point, at (0, 0.001 - sagitta) with sagitta
-- = 0.005 - sqrt(0.005^2 - 0.002^2).
local lowest = 0.001 - (0.005 - math.sqrt(0.005 ^ 2 - 0.002 ^ 2))
sim:add_particle { position = { 0, lowest + r + 2e-4 }, radius = r, material = "glass" }
sim:run { duration = 0.6 }
local w = sim:wall("cup")
assert(w.type == "polyline", "type " .. tostring(w.type))
local m = sim:particle(0).mass
assert(math.abs(w.force[2] + m * 9.81) < 1e-3 * m * 9.81,
       string.format("force %.6g against weight %.6g", w.force[2], m * 9.81))
-- At rest there, sunk by its weight over the stiffness.
local p = sim:particle(0).position
assert(math.abs(p[1]) < 1e-5, "x " .. p[1])
assert(math.abs(p[2] - (lowest + r)) < 1e-4 * r + m * 9.81 / 2000, "y " .. p[2])
assert(#sim:contacts() == 1, "one contact on the arc")
assert(sim:describe():find("wall cup: open polyline of 4 points, 3 segments (1 arcs)", 1, true),
       sim:describe())
print(string.format("polyline api: rests at y = %.6g m (arc bottom + r = %.6g)", p[2], lowest + r))

-- Moved later: set_wall lifts it; the disk goes up with it.
sim:set_wall("cup", { velocity = { 0, 0.01 } })
sim:run { duration = 0.1 }
local offset = sim:wall("cup").offset
assert(math.abs(offset[2] - 0.001) < 1e-6, "offset " .. offset[2])
assert(sim:particle(0).position[2] > p[2] + 0.0009, "lifted")
sim:set_wall("cup", { velocity = { 0, 0 } })
sim:set_wall("cup", { angular_velocity = 2 })
assert(sim:wall("cup").angular_velocity == 2)

-- Pictures draw the outline: a closed square of 4 straight segments adds 4 lines.
local function lines_in(file)
  local h = assert(io.open(file)); local text = h:read("a"); h:close(); os.remove(file)
  local n = 0
  for _ in text:gmatch("<line") do n = n + 1 end
  return n
end
local box = scene()
box:wall_polyline { name = "box", material = "steel", closed = true,
                    points = { { -0.01, -0.01 }, { 0.01, -0.01 }, { 0.01, 0.01 }, { -0.01, 0.01 } } }
box:add_particle { position = { 0, 0 }, radius = r, material = "glass" }
local svg_base = os.tmpname()
local svg = svg_base .. ".svg"
box:picture { file = svg, legend = false }
local with_walls = lines_in(svg)
box:picture { file = svg, legend = false, walls = false }
local without = lines_in(svg)
os.remove(svg_base)
assert(with_walls - without == 4, string.format("%d lines with walls, %d without", with_walls, without))
-- Arcs are drawn in pieces of at most 5 degrees: a circle of four quarter
-- arcs is 4 x 18 lines.
local ring = scene()
local R = 0.01
ring:wall_polyline { name = "ring", material = "steel", closed = true,
                     points = { { R, 0 }, { 0, R }, { -R, 0 }, { 0, -R } },
                     arcs = { { segment = 1, radius = -R }, { segment = 2, radius = -R },
                              { segment = 3, radius = -R }, { segment = 4, radius = -R } } }
ring:add_particle { position = { 0, 0 }, radius = r, material = "glass" }
ring:picture { file = svg, legend = false }
with_walls = lines_in(svg)
assert(with_walls - without == 72, string.format("%d lines with the ring, %d without", with_walls, without))

-- The XDMF walls file holds the outline as a polyline.
local base = os.tmpname()
local out = base .. ".h5"
box:output { file = out, xdmf = true }
box:snapshot {}
box:close()
local walls_file = out:gsub("%.h5$", "") .. "_walls.xmf"
local h = assert(io.open(walls_file)); local xmf = h:read("a"); h:close()
assert(xmf:find('Name="wall_box"', 1, true) and xmf:find("Polyline", 1, true), xmf)
os.remove(out); os.remove(walls_file); os.remove(base .. ".xmf"); os.remove(base)

-- Refusals, each naming the problem.
local function refused(fn, piece)
  local ok, err = pcall(fn)
  assert(not ok, "accepted: expected an error with '" .. piece .. "'")
  assert(tostring(err):find(piece, 1, true), "error '" .. tostring(err) .. "' lacks '" .. piece .. "'")
end
local two = { { 0, 0 }, { 0.01, 0 } }
refused(function() scene():wall_polyline { name = "l", material = "steel", points = { { 0, 0 } } } end,
        "at least 2 points")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = { { 0, 0 }, { 0 } } } end,
        "points[2]")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = { { 0, 0 }, { 0 / 0, 1 } } } end,
        "points[2]")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = two,
                                           arcs = { { segment = 2, radius = 0.01 } } } end, "arcs[1].segment = 2")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = two,
                                           arcs = { { segment = 1, radius = 0.001 } } } end,
        "arc radius of segment 1")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = two,
                                           arcs = { { segment = 1 } } } end, "radius")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = two, close = true } end,
        "did you mean 'closed'")
refused(function() scene():wall_polyline { name = "l", material = "steel" } end, "points")
refused(function() scene():wall_polyline { name = "l", material = "steel", points = two, solid = true } end,
        "solid = true needs closed = true")
refused(function() scene(3):wall_polyline { name = "l", material = "steel", points = two } end, "wall_mesh")
print("polyline api check ok")
