-- What a per-particle call costs as the scene grows: each should stay flat in N
-- (a user of LAMMPS or LIGGGHTS expects a move, a removal or an insertion to cost
-- the same in a bed of 1e3 as of 1e5). One scene per size: a touching cubic
-- lattice of N spheres (just overlapping), bonded (sim:bond) with record_contacts on, stepped
-- once; then, in microseconds per call:
--   add       sim:add_particle, the N calls that built the lattice;
--   move      sim:set_position (and a sim:particle read), `calls` of them in
--             shuffled id order, after a first one that indexes the bonds;
--   fill      sim:fill of 10 particles that may not overlap, in a box beside the
--             lattice (it looks at every particle once, to keep those within reach);
--   remove    sim:remove_particle, `calls` of them (bonds broken, recorded contacts
--             dropped), after a first one that makes the recorded list;
-- and, in a small scene of its own, what one snapshot costs (XDMF index on) over
-- the first and the last quarter of `snapshots` of them.
--   build/granule run tools/bench/call_costs.lua -q
--   build/granule run tools/bench/call_costs.lua -D sizes=1000,100000 -D snapshots=4000 -q
local p = parameters {
  sizes = { default = "1000,10000,100000", doc = "lattice sizes N, one scene each" },
  calls = { default = 1000, integer = true, min = 1, doc = "moves and removals timed per size" },
  snapshots = { default = 2000, integer = true, min = 4 },
}
local r = 1e-3

local function lattice(n)
  local sim = simulation { dimension = 3, time_step = 1e-7, record_contacts = true }
  sim:material { name = "g", density = 2500 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e4, restitution = 0.5, friction = 0.5 }
  local side = math.ceil(n ^ (1 / 3))
  local a = 2 * r * (1 - 1e-6)  -- just touching: every neighbour a contact
  local t = wall_time()
  for k = 0, n - 1 do
    local x, y, z = k % side, (k // side) % side, k // (side * side)
    sim:add_particle { position = { a * x, a * y, a * z }, radius = r, material = "g" }
  end
  local add = wall_time() - t
  sim:bond { gap = 1e-6 * r, normal_stiffness = 1e9, shear_stiffness = 1e9,
             tensile_strength = 1e12, shear_strength = 1e12 }
  sim:run { steps = 1 }
  return sim, add, side
end

local function shuffled(n, count, seed)
  local ids, state = {}, seed
  for k = 1, n do ids[k] = k - 1 end
  for k = n, 2, -1 do  -- Fisher-Yates with a small linear congruential generator
    state = (1103515245 * state + 12345) % 2147483648
    local j = state % k + 1
    ids[k], ids[j] = ids[j], ids[k]
  end
  local out = {}
  for k = 1, math.min(count, n) do out[k] = ids[k] end
  return out
end

print("| spheres | add, us | move, us | fill of 10, us | remove, us |")
print("|---|---|---|---|---|")
for text in string.gmatch(p.sizes, "[^,]+") do
  local n = math.tointeger(tonumber(text))
  assert(n and n > 0, "sizes: positive integers, got '" .. text .. "'")
  local sim, add, side = lattice(n)
  local ids = shuffled(n, p.calls, 7)
  local function move_up(id)
    local x = sim:particle(id).position
    sim:set_position(id, { x[1], x[2], x[3] + 1e-9 })
  end
  move_up(ids[1])  -- the first makes the bonds' index by particle (once, O(bonds)): untimed
  local t = wall_time()
  for k = 2, #ids do move_up(ids[k]) end
  local move = (wall_time() - t) / math.max(#ids - 1, 1)
  local top = 2 * r * side
  t = wall_time()
  for k = 1, 5 do
    sim:fill { region = { box = { lo = { 0, 0, top + 4 * r * k }, hi = { 2 * r * side, 2 * r * side, top + 4 * r * k + 3 * r } } },
               count = 10, radius = 0.5 * r, material = "g", seed = k, overlap = false }
  end
  local fill = (wall_time() - t) / 5
  -- The first removal turns the last step's contact log into a list by id
  -- (once, O(contacts)): untimed, so that the rest show the per-call cost.
  sim:remove_particle(ids[1])
  t = wall_time()
  for k = 2, #ids do sim:remove_particle(ids[k]) end
  local remove = (wall_time() - t) / math.max(#ids - 1, 1)
  local _ = sim:contacts()  -- the recorded list, the removed particles' contacts dropped
  print(string.format("| %d | %.2f | %.2f | %.0f | %.2f |", n, 1e6 * add / n, 1e6 * move,
    1e6 * fill, 1e6 * remove))
  sim:close()
end

-- Snapshots with the XDMF index: the last quarter should cost what the first does.
local out = os.tmpname()
local sim = simulation { dimension = 3, time_step = 1e-6 }
sim:material { name = "g", density = 2500 }
sim:contact { "g", "g", model = "linear", k_normal = 1e4, restitution = 0.5 }
sim:wall_plane { name = "floor", point = { 0, 0, -r }, normal = { 0, 0, 1 }, material = "g" }
for k = 0, 9 do sim:add_particle { position = { 3 * r * k, 0, 0 }, radius = r, material = "g" } end
sim:output { file = out .. ".h5", snapshot_every = 0 }
local quarter, first, last = p.snapshots // 4, 0, 0
for k = 1, 4 * quarter do
  local t = wall_time()
  sim:run { steps = 1 }
  sim:snapshot()
  local dt = wall_time() - t
  if k <= quarter then first = first + dt elseif k > 3 * quarter then last = last + dt end
end
sim:close()
print(string.format("snapshots (XDMF on): %.0f us each over the first quarter of %d, %.0f over the last",
  1e6 * first / quarter, 4 * quarter, 1e6 * last / quarter))
for _, suffix in ipairs { "", ".h5", ".xmf", "_walls.xmf" } do os.remove(out .. suffix) end
