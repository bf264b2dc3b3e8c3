-- One scene for the tests of `mpirun -np N granule run` (lua_over_ranks_test.sh):
-- each case runs two stages with callbacks that query the whole scene and set
-- a particle's velocity, snapshots and checkpoints, then prints every
-- particle's state and the walls' forces and torques in hex floats, all
-- bit-identical for any rank count. canonical = 1 asks a plain run for the
-- order every spread run uses (docs/parallel.md), so that its lines are the
-- same bits too.
local p = parameters {
  case = { default = "box", doc = "box (3D dense, Hertz-Mindlin) | sparse (the box, four particles in five removed, one more in the callback every 250 steps, and a friction ramp from step 500 to 540) | drum (3D, turning cylinder, linear) | jkr (3D agglomerate) | wb (2D Walton-Braun drum) | shear (3D shear cell, periodic along x, rolling and twisting resistance) | bonds (2D pile bonded, then tumbled in its drum) | mesh (3D pile on a triangle-mesh floor the scene writes)" },
  canonical = { default = 0 },
  checkpoint = { default = "over_ranks.chk.h5" },
  steps = { default = 0, doc = "steps of each of the two stages (0: the case's own)" },
  snapshots = { default = 6, doc = "snapshots in each stage (by simulated time)" },
}
-- A 2D drum of radius 6 mm filled with powder: `law` (model and its values)
-- for powder on powder, with friction mu_pp, and on the steel drum with 0.5.
local function drum_2d(law, mu_pp, spin, fill)
  local s = simulation { dimension = 2, record_contacts = true }
  s:material { name = "powder", density = 1200 }
  s:material { name = "steel", density = 7800 }
  for _, pair in ipairs { { "powder", mu_pp }, { "steel", 0.5 } } do
    local c = { "powder", pair[1], friction = pair[2] }
    for k, v in pairs(law) do c[k] = v end
    s:contact(c)
  end
  s:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 6e-3, angular_velocity = spin, material = "steel" }
  fill.region = { circle = { center = { 0, 0 }, radius = 6e-3 } }
  fill.material, fill.seed, fill.overlap = "powder", 3, false
  s:fill(fill)
  return s
end
local sim
if p.case == "bonds" then
  -- A 2D pile settles in its drum; between the stages its touching pairs are
  -- bonded and the drum turns, so that bonds load, stretch across the ranks'
  -- boxes and break.
  sim = drum_2d({ model = "linear", k_normal = 2e3, restitution = 0.5 }, 0.3, 0, { count = 200, radius = 0.3e-3 })
  sim:gravity { 0, -400 }  -- settles within the first stage
elseif p.case == "wb" then
  sim = drum_2d({ model = "walton_braun", k_load = 2e4, restitution = 0.85 }, 0.1, 150,
                { count = 350, radius = 0.2e-3, max_speed = 2 })
  sim:gravity { 0, -9.81 }
else
  -- The shear cell: periodic along x, so its ghosts cross the period.
  local period = 6e-3
  sim = simulation { dimension = 3, record_contacts = true,
                     periodic = p.case == "shear" and { axis = "x", origin = 0, length = period } or nil }
  sim:material { name = "glass", density = 2500, young = 5e7, poisson = 0.3, surface_energy = 0.05 }
  sim:material { name = "steel", density = 7800, young = 2e8, poisson = 0.3 }
  if p.case == "box" or p.case == "sparse" then
    sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.6, friction = 0.4 }
    sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.6, friction = 0.4 }
    local w = 3e-3
    for _, plane in ipairs {
      { "floor", { 0, -w, 0 }, { 0, 1, 0 } }, { "left", { -w, 0, 0 }, { 1, 0, 0 } },
      { "right", { w, 0, 0 }, { -1, 0, 0 } }, { "back", { 0, 0, -w }, { 0, 0, 1 } },
      { "front", { 0, 0, w }, { 0, 0, -1 } } } do
      sim:wall_plane { name = plane[1], point = plane[2], normal = plane[3], material = "steel" }
    end
    sim:fill { region = { box = { lo = { -w, -w, -w }, hi = { w, w, w } } }, count = 900, radius = 0.25e-3,
               material = "glass", seed = 5, max_speed = 0.2, overlap = false }
    sim:gravity { 0, -9.81, 0 }
    -- sparse: four particles in five removed, so that the ids are sparse
    -- (the spread totals then sum in id order by sorting, not by placing).
    if p.case == "sparse" then
      for _, id in ipairs(sim:particles()) do
        if id % 5 ~= 0 then sim:remove_particle(id) end
      end
    end
  elseif p.case == "drum" then
    sim:contact { "glass", "glass", model = "linear", k_normal = 2e3, restitution = 0.7, friction = 0.3 }
    sim:contact { "glass", "steel", model = "linear", k_normal = 2e3, restitution = 0.7, friction = 0.5 }
    sim:wall_cylinder { name = "drum", center = { 0, 0, 0 }, axis = { 0, 0, 1 }, radius = 4e-3,
                        angular_velocity = 60, material = "steel" }
    sim:wall_plane { name = "back", point = { 0, 0, -1.5e-3 }, normal = { 0, 0, 1 }, material = "steel" }
    sim:wall_plane { name = "front", point = { 0, 0, 1.5e-3 }, normal = { 0, 0, -1 }, material = "steel" }
    sim:fill { region = { cylinder = { center = { 0, 0, 0 }, radius = 4e-3, z_min = -1.5e-3, z_max = 1.5e-3 } },
               count = 500, radius = 0.2e-3, material = "glass", seed = 7, max_speed = 1, overlap = false }
    sim:gravity { 0, -9.81, 0 }
  elseif p.case == "shear" then
    -- Beads between a floor and a lid sliding apart along x (the lid also
    -- closing in), smooth side walls in z; rolling and twisting resistance,
    -- whose springs travel with the contacts across ranks and periods.
    sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = 0.4,
                  rolling_friction = 0.1, twisting_friction = 0.1, rolling_damping = 0.3 }
    sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.5, friction = 0.8,
                  rolling_friction = 0.05, twisting_friction = 0.05 }
    local height, width = 4e-3, 3e-3
    sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "steel" }
    sim:wall_plane { name = "lid", point = { 0, height, 0 }, normal = { 0, -1, 0 }, material = "steel" }
    sim:wall_plane { name = "back", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
    sim:wall_plane { name = "front", point = { 0, 0, width }, normal = { 0, 0, -1 }, material = "steel" }
    sim:set_wall("floor", { velocity = { -0.1, 0, 0 } })
    sim:set_wall("lid", { velocity = { 0.1, -0.07, 0 } })
    sim:fill { region = { box = { lo = { 0, 0, 0 }, hi = { period, height, width } } }, count = 300, radius = 0.25e-3,
               material = "glass", seed = 13, max_speed = 0.2, overlap = false }
    sim:gravity { 0, -9.81, 0 }
  elseif p.case == "mesh" then
    -- A pile falling onto a triangle-mesh floor the scene writes itself
    -- (every rank reads back its own copy of the file).
    local shapes = require "granule.mesh_shapes"
    sim:contact { "glass", "glass", model = "hertz_mindlin", restitution = 0.5, friction = 0.4 }
    sim:contact { "glass", "steel", model = "hertz_mindlin", restitution = 0.5, friction = 0.6 }
    local path = shapes.box { corner = { -3e-3, -4e-3, -3e-3 }, edges = { { 6e-3, 0, 0 }, { 0, 1e-3, 0 }, { 0, 0, 6e-3 } } }
    sim:wall_mesh { name = "floor", file = path, material = "steel" }
    os.remove(path)
    sim:fill { region = { box = { lo = { -2.5e-3, -2.5e-3, -2.5e-3 }, hi = { 2.5e-3, 2.5e-3, 2.5e-3 } } }, count = 400,
               radius = 0.25e-3, material = "glass", seed = 17, max_speed = 0.1, overlap = false }
    sim:gravity { 0, -200, 0 }
  elseif p.case == "jkr" then
    sim:contact { "glass", "glass", model = "thornton_jkr", friction = 0.3 }
    -- a cloud pulled together by a central field: JKR necks form and hold
    sim:fill { region = { sphere = { center = { 0, 0, 0 }, radius = 1.5e-3 } }, count = 300, radius = 0.1e-3,
               material = "glass", seed = 11, max_speed = 0.05, overlap = false }
    sim:central_field { point = { 0, 0, 0 }, strength = 20 }
  else
    error("case: box, sparse, drum, jkr, wb, shear, bonds or mesh, not '" .. p.case .. "'")
  end
end
local steps = p.steps > 0 and p.steps or ({ box = 8000, sparse = 3000, drum = 8000, jkr = 4000, wb = 10000, shear = 8000, bonds = 8000, mesh = 6000 })[p.case]
if p.canonical == 1 then sim:set { canonical_order = true } end
-- sparse: a friction ramp over 40 steps of the first stage, from step 500: a
-- schedule that changes a law prepares the scene whole (spread: gathered).
if p.case == "sparse" then
  local dt = sim:time_step()
  sim:schedule { "friction", from = "glass", to = "glass", linear = { 500 * dt, 0.4, 540 * dt, 0.2 } }
end
sim:output { snapshot_every = steps * sim:time_step() / p.snapshots }
sim:checkpoint { file = p.checkpoint, every_steps = 1000 }
-- A callback that reads the whole scene and sets state wherever the particle lives.
local energies, contact_sums = {}, {}
-- The last step's contacts, in the order sim:contacts() lists them: the
-- normal forces summed in that order (another order rounds differently).
local function contact_sum(s)
  local sum, list = 0, s:contacts()
  for _, c in ipairs(list) do sum = sum + c.normal_force * (c.b or -#c.wall) end
  return string.format("%d %a", #list, sum)
end
-- A callback that reads only the totals (spread runs keep their shares for it).
local monitored = {}
sim:every { steps = 70, function(s)
  local st = s:stats()
  monitored[#monitored + 1] = string.format("%d %a %a %a %d %d %d %d", s:step_count(), s:time(), st.kinetic_energy,
    st.kinetic_energy_rotational, st.contacts_particle, st.contacts_batched, st.contacts_wall,
    st.contacts_wall_batched)
end }
-- The shear cell's floor shaken from a callback that reads the time and sets a
-- wall's velocity (spread runs keep their shares for it, as for a shaken floor
-- set every step).
if p.case == "shear" then
  sim:every { steps = 3, function(s)
    s:set_wall("floor", { velocity = { -0.1, 0.02 * math.sin(2 * math.pi * 2000 * s:time()), 0 } })
  end }
end
local held  -- box: the particle fixed at one firing and freed at the next
sim:every { steps = 250, function(s)
  local st = s:stats()
  energies[#energies + 1] = st.kinetic_energy
  local bonds = s:bond_counts()
  contact_sums[#contact_sums + 1] = contact_sum(s) .. string.format(" bonds %d %d", bonds.intact, bonds.broken)
  local ids = s:particles()
  local id = ids[(#energies * 37) % #ids + 1]
  local v = s:particle(id).velocity
  v[1] = v[1] + 1e-3
  if not s:particle(id).fixed then s:set_velocity(id, v) end
  if p.case == "box" then
    -- sim:set_fixed mid-run: the lists and the time step made anew on every
    -- rank, and the free mass the stats reduce over the ranks; the fixed one moving.
    if held then
      s:set_fixed(held, false)
      held = nil
    else
      held = ids[(#energies * 29) % #ids + 1]
      s:set_fixed(held, true)
      -- Prescribed motion: it rises through the bed at a set speed, whatever
      -- touches it (its ghosts follow it); freed at the next firing, it goes on.
      local up = s:particle(held).velocity
      up[2] = 0.1
      s:set_velocity(held, up)
    end
    contact_sums[#contact_sums] = contact_sums[#contact_sums] .. string.format(" free_mass %a", s:stats().free_mass)
  end
  if p.case == "sparse" then
    -- A particle leaves mid-run, as an outflow removes one: the last step's
    -- contacts are then those without it, the same records in the same order
    -- (it had some), and the next step and a checkpoint after it go on from there.
    local gone = ids[(#energies * 53) % #ids + 1]
    local kept, had = {}, 0
    for _, c in ipairs(s:contacts()) do
      if c.a == gone or c.b == gone then had = had + 1 else kept[#kept + 1] = c end
    end
    s:remove_particle(gone)
    local now = s:contacts()
    assert(#now == #kept, string.format("%d contacts after removing %d, expected %d", #now, gone, #kept))
    for k, c in ipairs(now) do
      assert(c.a == kept[k].a and c.b == kept[k].b and c.wall == kept[k].wall and
             c.normal_force == kept[k].normal_force, "contact " .. k .. " changed by a removal")
    end
    contact_sums[#contact_sums] = contact_sums[#contact_sums] ..
      string.format(" removed %d with %d contacts, then %s", gone, had, contact_sum(s))
  end
end }
sim:run { steps = steps }
if p.case == "jkr" then sim:set_central_strength(0) end
if p.case == "bonds" then
  print("bonds made " .. sim:bond { normal_stiffness = 2e9, shear_stiffness = 1e9, tensile_strength = 2e4,
                                    shear_strength = 2e4, gap = 2e-5 })
  sim:set_wall("drum", { angular_velocity = 300 })
end
-- The stop check reads the totals (the shares kept) and then a particle (the scene gathered).
sim:run { steps = steps, check_every = 500, stop_when = function(s)
  return s:stats().kinetic_energy < 0 or s:particle(s:particles()[1]).radius < 0
end }
local st = sim:stats()
print(string.format("stats %d %d %a %d %d", sim:step_count(), st.particles, st.kinetic_energy,
  st.contacts_particle, st.contacts_wall))
for k, e in ipairs(energies) do print(string.format("energy %d %a %s", k, e, contact_sums[k])) end
for k, line in ipairs(monitored) do print("monitored " .. k .. " " .. line) end
for _, c in ipairs(sim:contacts()) do
  local line = { "contact", c.model, tostring(c.a), tostring(c.b or c.wall),
                 string.format("%a %a", c.overlap, c.normal_force) }
  for _, vec in ipairs { c.tangential_force, c.normal } do
    for _, x in ipairs(vec) do line[#line + 1] = string.format("%a", x) end
  end
  print(table.concat(line, " "))
end
local view = sim:contact_arrays()
assert(#view == #sim:contacts(), "contact_arrays and contacts() disagree")
local view_sum = 0
for k = 1, #view do view_sum = view_sum + view.fn[k] * view.i[k] + view.nx[k] end
print(string.format("contact_arrays %d %a", #view, view_sum))
for _, id in ipairs(sim:particles()) do
  local q = sim:particle(id)
  local line = { "state", tostring(id) }
  for _, vec in ipairs { q.position, q.velocity, q.spin, q.force } do
    if type(vec) == "number" then vec = { vec } end  -- a 2D spin
    for _, c in ipairs(vec) do line[#line + 1] = string.format("%a", c) end
  end
  print(table.concat(line, " "))
end
local bonds = sim:bond_counts()
print(string.format("bond_counts %d %d", bonds.intact, bonds.broken))
local walls = ({ box = { "floor", "left", "right", "back", "front" }, sparse = { "floor", "left", "right", "back", "front" }, drum = { "drum", "back", "front" }, bonds = { "drum" }, mesh = { "floor" },
                jkr = {}, wb = { "drum" }, shear = { "floor", "lid", "back", "front" } })[p.case]
for _, name in ipairs(walls) do
  local wall = sim:wall(name)
  print(string.format("wall %s %a %a %a %a", name, wall.force[1], wall.force[2],
    wall.force[3] or 0, wall.torque or 0))
end
