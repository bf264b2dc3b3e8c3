-- A disk whose centre is inside a solid polyline is pushed back out through the nearest
-- point of the line (mesh_contacts.hpp), at any depth; a hollow one's disk stays inside.
local function case(depth_in_radii, solid)
  local sim = simulation { dimension = 2 }
  sim:material { name = "g", density = 2500 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0 }
  local r = 1e-3
  sim:wall_polyline { name = "block", material = "g", closed = true, solid = solid,
                      points = { { 0, 0 }, { 0.02, 0 }, { 0.02, 0.02 }, { 0, 0.02 } } }
  -- Centre depth_in_radii * r inside the left face, at mid-height.
  local id = sim:add_particle { position = { depth_in_radii * r, 0.01 }, radius = r, material = "g" }
  sim:run { duration = 0.02 }
  local q = sim:particle(id)
  return q.position[1], q.velocity[1]
end
for _, depth in ipairs { 0.3, 1.5, 4 } do
  local x, vx = case(depth, true)
  print(string.format("solid depth %.1f r: x = %.4g m, vx = %.4g m/s", depth, x, vx))
  assert(x < -1e-3 + 1e-9 and vx < 0, "a disk inside a solid polyline was not pushed out")
end
local x = case(0.3, false)
print(string.format("hollow depth 0.3 r: x = %.4g m", x))
assert(x > 0, "a hollow polyline pushed its disk out through the line")
print("solid polyline push-out ok")
