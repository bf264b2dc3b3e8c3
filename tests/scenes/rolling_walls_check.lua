-- Rolling resistance on every kind of wall: a sphere rolling to rest against
-- rolling friction (constant torque and EPSD) on a plane, on a mesh floor (3D,
-- a box of triangles) and on a polyline floor (2D, one segment) stops at the
-- same point, bit for bit: the rolling term acts on the wall contact whatever
-- surface found it.
local shapes = require "granule.mesh_shapes"
local function run(d, kind, model)
  local sim = simulation { dimension = d }
  sim:material { name = "ball", density = 2500 }
  sim:material { name = "floor", density = 0 }
  for _, o in ipairs { "ball", "floor" } do
    sim:contact { "ball", o, model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.9,
                  rolling_friction = 0.1, rolling_model = model, rolling_damping = model == "epsd" and 0.3 or nil }
  end
  local function v(x, y) if d == 3 then return { x, y, 0 } end return { x, y } end
  if kind == "plane" then
    sim:wall_plane { name = "floor", point = v(0, 0), normal = v(0, 1), material = "floor" }
  elseif kind == "mesh" then
    local path = shapes.box { corner = { -0.05, -0.01, -0.05 }, edges = { { 0.1, 0, 0 }, { 0, 0.01, 0 }, { 0, 0, 0.1 } } }
    sim:wall_mesh { name = "floor", file = path, material = "floor" }
    os.remove(path)
  else
    sim:wall_polyline { name = "floor", points = { { -0.05, 0 }, { 0.05, 0 } }, material = "floor" }
  end
  sim:gravity(v(0, -9.81))
  local m = 2500 * 4 / 3 * math.pi * 1e-9
  local id = sim:add_particle { position = v(0, 1e-3 - m * 9.81 / 1e3), velocity = v(0.1, 0), radius = 1e-3,
                                spin = d == 3 and { 0, 0, -100 } or -100, material = "ball" }
  sim:run { duration = 0.25 }
  local p = sim:particle(id)
  assert(math.abs(p.velocity[1]) < 1e-4, string.format("%dD %s %s: still rolling at %g m/s", d, kind, model, p.velocity[1]))
  return p.position[1]
end
for _, model in ipairs { "constant", "epsd" } do
  local plane3, mesh = run(3, "plane", model), run(3, "mesh", model)
  local plane2, polyline = run(2, "plane", model), run(2, "polyline", model)
  assert(mesh == plane3, string.format("%s: mesh floor %.17g m, plane %.17g m", model, mesh, plane3))
  assert(polyline == plane2, string.format("%s: polyline floor %.17g m, plane %.17g m", model, polyline, plane2))
  -- and the distance is the closed form's 0.7 v0^2 / (mu_r g) = 7.136 mm within 1 %
  assert(math.abs(plane3 / (0.7 * 0.01 / (0.1 * 9.81)) - 1) < 0.01, "distance " .. plane3)
  print(string.format("rolling_walls: %s stops at %.6g m on plane, mesh and polyline", model, plane3))
end
print("rolling_walls ok")
