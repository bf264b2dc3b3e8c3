-- sim:arrays() and sim:contact_arrays() (src/lua/wrap_views.cpp) against the per-particle and
-- per-contact queries they stand for, in 2D and 3D: the same numbers, exactly; read-only;
-- indices outside 1..# refused; reading every element of every column makes no garbage.
local function check(dimension)
  local sim = simulation { dimension = dimension, time_step = 1e-6, record_contacts = true }
  sim:material { name = "glass", density = 2500 }
  sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.9, friction = 0.3 }
  local zero = dimension == 2 and { 0, 0 } or { 0, 0, 0 }
  local up = dimension == 2 and { 0, 1 } or { 0, 0, 1 }
  sim:wall_plane { name = "floor", material = "glass", point = zero, normal = up }
  sim:gravity(dimension == 2 and { 0, -9.81 } or { 0, 0, -9.81 })
  local r = 1e-3
  for k = 0, 5 do
    local x, h = k * (2 * r - 2e-5), r - 1e-5 + (k % 2) * 3e-3
    sim:add_particle { position = dimension == 2 and { x, h } or { x, 0.1 * x, h },
                       velocity = dimension == 2 and { 0.01 * k, 0 } or { 0.01 * k, 0, -0.01 },
                       spin = dimension == 2 and 3 * k or { k, 0, 2 * k }, radius = r * (1 + 0.01 * k),
                       material = "glass" }
  end
  sim:run { steps = 30 }
  local P, C = sim:arrays(), sim:contact_arrays()
  assert(#P == 6 and #P.x == 6, "#P")
  local comps = dimension == 2 and { "x", "y" } or { "x", "y", "z" }
  for i = 1, #P do
    local b = sim:particle(P.id[i])
    assert(math.type(P.id[i]) == "integer" and math.type(P.material[i]) == "integer", "integer ids")
    assert(P.radius[i] == b.radius, "radius")
    for k, c in ipairs(comps) do
      assert(P[c][i] == b.position[k], "position " .. c)
      assert(P["v" .. c][i] == b.velocity[k], "velocity " .. c)
      assert(P["f" .. c][i] == b.force[k], "force " .. c)
    end
    if dimension == 2 then
      assert(P.wz[i] == b.spin and P.z[i] == 0 and P.wx[i] == 0, "2D spin and z")
    else
      for k, c in ipairs(comps) do assert(P["w" .. c][i] == b.spin[k], "spin " .. c) end
    end
  end
  local list = sim:contacts()
  assert(#C == #list and #C > 0, string.format("%d contact rows, sim:contacts() has %d", #C, #list))
  for k = 1, #C do
    local c = list[k]
    assert(C.i[k] == c.a and C.overlap[k] == c.overlap and C.fn[k] == c.normal_force, "contact " .. k)
    if c.wall then
      assert(C.j[k] == -1 and sim:walls()[C.wall[k] + 1] == c.wall, "wall contact " .. k)
    else
      assert(C.j[k] == c.b and C.wall[k] == -1, "pair contact " .. k)
    end
    for d, comp in ipairs(comps) do
      assert(C["t" .. comp][k] == c.tangential_force[d] and C["n" .. comp][k] == c.normal[d], "vectors")
    end
  end
  -- Errors, not nil: a misspelt column, an index out of range, a write.
  local ok, err = pcall(function() return P.velocity end)
  assert(not ok and err:find("no array 'velocity'"), err)
  ok, err = pcall(function() return P.x[7] end)
  assert(not ok and err:find("outside 1..6"), err)
  ok, err = pcall(function() P.x[1] = 0 end)
  assert(not ok and err:find("read%-only"), err)
  -- Allocation-free: a sweep over every column once the columns are in hand.
  local columns = {}
  for _, name in ipairs { "id", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz",
                          "radius", "material" } do columns[#columns + 1] = P[name] end
  local cc = { C.i, C.j, C.wall, C.overlap, C.fn, C.tx, C.nx }
  collectgarbage("stop")
  local before, sum = collectgarbage("count"), 0
  for _ = 1, 200 do
    for _, col in ipairs(columns) do for i = 1, #col do sum = sum + col[i] end end
    for _, col in ipairs(cc) do for k = 1, #col do sum = sum + col[k] end end
  end
  local grown = collectgarbage("count") - before
  collectgarbage("restart")
  assert(grown == 0, string.format("reading the views made %.1f KiB of garbage", grown))
  -- The views follow the simulation: after more steps they read the new state.
  sim:run { steps = 5 }
  assert(P.x[1] == sim:particle(P.id[1]).position[1], "a view reads the current step")
  return #C
end
print(string.format("views_check ok: %d contacts in 2D, %d in 3D", check(2), check(3)))
