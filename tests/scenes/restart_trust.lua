-- Scenes whose restart must either continue the first run or be refused by name
-- (tests/scenes/restart_trust_test.py runs each case).
local p = parameters {
  case = { default = "pairs", doc = "pairs | args | module | mesh | pcall | prerun | replay_stop | views | second | history | other_file | mesh_file | attach | last_step" },
  dimension = { default = 3, integer = true, min = 2, max = 3, doc = "last_step: the scene's dimension" },
}
if p.case == "mesh" then
  -- A mesh written to a file os.tmpname names (another name in every process), which
  -- sim:wall_mesh is given: the restart replays the first run's name.
  local shapes = require "granule.mesh_shapes"
  local sim = simulation { dimension = 3 }
  sim:material { name = "g", density = 2500 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5 }
  local path = shapes.prism { center = { 0, 0 }, radius = 5e-3, facets = 12, z_min = 0, z_max = 2e-3 }
  sim:wall_mesh { name = "drum", file = path, material = "g" }
  os.remove(path)
  sim:add_particle { position = { 0, -3e-3, 1e-3 }, radius = 0.5e-3, material = "g" }
  sim:gravity { 0, -9.81, 0 }
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  print(string.format("mesh done, y %.17g", sim:particle(0).position[2]))
  return
elseif p.case == "last_step" then
  -- What a script reads of the last step between runs (the recorded contacts, the
  -- walls' reactions, stats()' tallies), read after a checkpoint written between
  -- runs: the restart must read what the whole run read (the test runs 2D and 3D).
  local function report(sim, dimension, stepped)
    local c = sim:contacts()
    local normal, tangential = 0, 0
    for _, r in ipairs(c) do
      normal = normal + r.normal_force
      tangential = tangential + r.tangential_force[1] + r.overlap + r.normal[1]
      if r.b then tangential = tangential + r.b elseif r.wall == "floor" then tangential = tangential + 1e3 end
    end
    local s = sim:stats()
    local floor = sim:wall("floor")
    print(string.format("%dD: %d contacts (%s), %d in arrays, normal sum %.17g, other %.17g", dimension,
                        #c, c[1] and c[1].model or "-", #sim:contact_arrays().overlap, normal, tangential))
    print(string.format("%dD: floor force %.17g %.17g, torque %.17g", dimension, floor.force[1],
                        floor.force[dimension], floor.torque))
    -- The pruned lists are noted afresh after a restart (they change no result), so
    -- their counters match only before the restart's first step.
    local pruning = stepped and "" or string.format(" %d %d", s.pair_candidates_visited,
                                                     s.pair_list_prunes)
    print(string.format("%dD: stats %d %d %d %d%s %.17g", dimension, s.contacts_particle,
                        s.contacts_batched, s.contacts_wall, s.contacts_wall_batched, pruning,
                        s.max_overlap_ratio))
  end
  do
    local dimension = p.dimension
    local sim = simulation { dimension = dimension, record_contacts = true }
    sim:material { name = "g", density = 2500, young = 1e7, poisson = 0.3 }
    if dimension == 3 then
      sim:contact { "g", "g", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
    else
      sim:contact { "g", "g", model = "walton_braun", k_load = 2e4, restitution = 0.5, friction = 0.3 }
    end
    local up = dimension == 3 and { 0, 0, 1 } or { 0, 1 }
    sim:wall_plane { name = "floor", point = dimension == 3 and { 0, 0, 0 } or { 0, 0 }, normal = up,
                     material = "g" }
    for k, side in ipairs { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 } } do
      if dimension == 3 or side[2] == 0 then  -- a box in 3D, a channel in 2D
        local point = { -2.2e-3 * side[1], -2.2e-3 * side[2], 0 }
        if dimension == 2 then point[3], side[3] = nil, nil end
        sim:wall_plane { name = "side" .. k, point = point, normal = side, material = "g" }
      end
    end
    sim:gravity(dimension == 3 and { 0, 0, -9.81 } or { 0, -9.81 })
    sim:fill { region = { box = { lo = dimension == 3 and { -2e-3, -2e-3, 0 } or { -2e-3, 0 },
                                  hi = dimension == 3 and { 2e-3, 2e-3, 6e-3 } or { 2e-3, 6e-3 } } },
               count = dimension == 3 and 30 or 12, radius = 0.4e-3, material = "g", seed = 3,
               overlap = false }
    sim:run { duration = 0.05 }
    sim:save_checkpoint("trust.chk.h5")
    report(sim, dimension)
    sim:run { steps = 10 }
    report(sim, dimension, true)
  end
  return
elseif p.case == "mesh_file" then
  -- A mesh file the test writes, and edits after the checkpoint: the restart is refused.
  local sim = simulation { dimension = 3 }
  sim:material { name = "g", density = 2500 }
  sim:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5 }
  sim:wall_mesh { name = "floor", file = "trust_floor.obj", material = "g" }
  sim:add_particle { position = { 0, 0, 0.6e-3 }, radius = 0.5e-3, material = "g" }
  sim:gravity { 0, 0, -9.81 }
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  print("mesh_file done")
  return
end
local sim = simulation { dimension = 2 }
sim:material { name = "g", density = 2500 }
sim:contact { "g", "g", model = "walton_braun", k_load = 2e4, restitution = 0.8, friction = 0.3 }
sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 4e-3, material = "g" }
sim:gravity { 0, -9.81 }

local function fill(count, seed, y)
  return sim:fill { region = { box = { lo = { -1.5e-3, y }, hi = { 1.5e-3, y + 0.8e-3 } } }, count = count,
                    radius = 0.15e-3, material = "g", seed = seed, overlap = false }
end

if p.case == "pairs" then
  -- One group per key of a table with string keys: made in pairs() order, which must not
  -- change from one process to the next (Lua's own order does).
  local groups = { top = 2, middle = 3, bottom = 4, left = 5, right = 6, far = 7, near = 3 }
  local ids, order = {}, {}
  local y = -3e-3
  for name, count in pairs(groups) do
    ids[name] = fill(count, count, y)
    order[#order + 1] = name
    y = y + 0.85e-3
  end
  print("order " .. table.concat(order, " "))
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  local first = sim:particle(ids.top[1])
  print(string.format("top %d first y %.17g", #ids.top, first.position[2]))
elseif p.case == "args" then
  -- A call's arguments read from the environment, which the journal does not keep.
  fill(tonumber(os.getenv("GRANULE_TRUST_COUNT") or "10"), 1, -2e-3)
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  print("args done")
elseif p.case == "module" then
  local helper = require "trust_helper"  -- written by the test into its folder
  fill(helper.count, 1, -2e-3)
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  print("module done")
elseif p.case == "pcall" then
  -- A scene that catches its run's errors: a signal must still end it.
  fill(12, 1, -2e-3)
  for stage = 1, 3 do
    print("stage " .. stage)
    io.stdout:flush()
    local ok, err = pcall(sim.run, sim, { duration = 5 })
    -- The message without its "file:line: " (its length depends on where the tree is).
    local message = tostring(err):gsub("^.-:%d+: ", ""):match("[^\n]*")
    print("stage " .. stage .. (ok and " ran" or " failed: " .. message))
  end
  print("pcall went on to its end")
elseif p.case == "prerun" then
  fill(10, 1, -2e-3)
  print("busy")
  io.stdout:flush()
  local x = 0
  for k = 1, 1e10 do x = x + math.sin(k) end
  sim:run { duration = 1e-3 }
elseif p.case == "replay_stop" then
  -- Lua work in the past the restart replays (as long as the environment says: it is no
  -- engine call's argument), stopped there by the test.
  fill(12, 1, -2e-3)
  sim:run { duration = 1e-3 }
  print("busy")
  io.stdout:flush()
  local x = 0
  for k = 1, tonumber(os.getenv("GRANULE_TRUST_LOOP") or "10") do x = x + math.sin(k) end
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 1e-3 }
  print("replay_stop done")
elseif p.case == "views" then
  fill(12, 1, -2e-3)
  local P = sim:arrays()
  local sum = 0
  sim:every { steps = 50, function() for i = 1, #P do sum = sum + P.vy[i] end end }
  sim:run { duration = 2e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 2e-3 }
  print(string.format("views sum %.6g", sum))
elseif p.case == "second" then
  -- A second simulation, used again after the checkpoint: the restart rebuilds it without
  -- its state, so its use after the checkpoint's point is refused.
  fill(12, 1, -2e-3)
  local other = simulation { dimension = 2 }
  other:material { name = "g", density = 2500 }
  other:contact { "g", "g", model = "linear", k_normal = 1e3, restitution = 0.5 }
  other:add_particle { position = { 0, 0 }, radius = 1e-3, material = "g" }
  other:gravity { 0, -9.81 }
  sim:run { duration = 1e-3 }
  other:run { duration = 1e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 1e-3 }
  other:run { duration = 1e-3 }
  print(string.format("second done, y %.6g", other:particle(0).position[2]))
elseif p.case == "history" then
  -- The output gets contact histories after the run (as an agglomerate's preparation): a
  -- restart from a checkpoint before them, after the whole run ended, writes them again.
  fill(12, 1, -2e-3)
  local out = sim:output { file = "history.h5", snapshot_every = 5e-4 }
  sim:run { duration = 1e-3 }
  sim:save_checkpoint("trust.chk.h5")
  sim:run { duration = 1e-3 }
  sim:close()
  sim:save_contact_histories { file = out }
  print("history done")
elseif p.case == "other_file" then
  -- Another run writes the output's file anew after the checkpoint: the restart is refused.
  fill(12, 1, -2e-3)
  sim:output { file = "other.h5" }
  sim:run { duration = 1e-3 }
  sim:save_checkpoint(os.getenv("GRANULE_TRUST_CHECKPOINT") or "trust.chk.h5")
  sim:run { duration = 1e-3 }
  print("other_file done")
elseif p.case == "attach" then
  -- A diagnostic that follows contacts, attached after the checkpoint's point to a
  -- settled bed: the restart takes over first, and must count what the whole run counts.
  fill(12, 1, -3.0e-3)
  fill(12, 2, -2.15e-3)
  sim:wall_cylinder { name = "inner_piece", center = { 1.5e-3, 0 }, radius = 1e-3, inside = false, material = "g" }
  sim:output { file = "attach.h5", snapshot_every = 0 }
  sim:run { duration = 30e-3 }
  sim:save_checkpoint("trust.chk.h5")
  local id = sim:diagnostic("areas", { chamber = "drum", inner_piece = "inner_piece", every = 1, window = 1e-3 })
  sim:set_wall("drum", { angular_velocity = 100 })
  sim:run { duration = 5e-3 }
  local r = sim:diagnostic_results(id)
  print(string.format("attach collisions %g %g %g", r.collisions_particle_input, r.collisions_particle_free_diffusion,
                      r.collisions_boundary_scraper))
end
