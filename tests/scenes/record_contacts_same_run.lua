-- Recording the contacts observes a run without changing it: a pile poured onto
-- a floor ends in the same bits with record_contacts on and off, for laws on the
-- per-contact path (Hertz-Mindlin with rolling resistance, JKR) and the batched
-- one, in 2D and 3D (the recording is a run-time branch of the per-contact pass,
-- so the compiler fuses the same multiply-adds either way).
local function pile(dimension, law, record)
  local sim = simulation { dimension = dimension, record_contacts = record }
  sim:material { name = "g", density = 2500, young = 5e7, poisson = 0.25, surface_energy = 0.01 }
  sim:material { name = "s", density = 7800, young = 5e7, poisson = 0.3, surface_energy = 0.01 }
  for _, m in ipairs { "g", "s" } do
    if law == "jkr" then
      sim:contact { "g", m, model = "thornton_jkr", friction = 0.5 }
    else
      sim:contact { "g", m, model = "hertz_mindlin", restitution = 0.5, friction = 0.5,
                    rolling_friction = law == "rolling" and 0.1 or 0 }
    end
  end
  local up = dimension == 3 and { 0, 0, 1 } or { 0, 1 }
  sim:wall_plane { name = "floor", point = dimension == 3 and { 0, 0, 0 } or { 0, 0 }, normal = up,
                   material = "s" }
  -- Side walls, so that the pile stays a pile.
  local half = dimension == 3 and 0.005 or 0.015
  for axis = 1, dimension - 1 do
    for _, sign in ipairs { -1, 1 } do
      local point, normal = { 0, 0, 0 }, { 0, 0, 0 }
      point[axis], normal[axis] = sign * half, -sign
      if dimension == 2 then point[3], normal[3] = nil, nil end
      sim:wall_plane { name = "side" .. axis .. sign, point = point, normal = normal, material = "s" }
    end
  end
  local region = dimension == 3 and { box = { lo = { -0.005, -0.005, 0 }, hi = { 0.005, 0.005, 0.02 } } }
                 or { box = { lo = { -0.015, 0 }, hi = { 0.015, 0.025 } } }
  sim:fill { region = region, count = 100, radius = 1e-3, material = "g", seed = 3, overlap = false }
  sim:gravity(dimension == 3 and { 0, 0, -9.81 } or { 0, -9.81 })
  sim:run { duration = 0.12 }
  local bits = {}
  for _, id in ipairs(sim:particles()) do
    local b = sim:particle(id)
    for k = 1, dimension do bits[#bits + 1] = string.format("%a %a", b.position[k], b.velocity[k]) end
  end
  return table.concat(bits, " "), sim:stats().contacts_particle
end
for _, dimension in ipairs { 2, 3 } do
  for _, law in ipairs { "rolling", "jkr", "plain" } do
    local off, contacts = pile(dimension, law, false)
    local on = pile(dimension, law, true)
    assert(contacts > 20, string.format("%dD %s: only %d contacts: not a pile", dimension, law, contacts))
    assert(off == on, string.format("%dD %s: recording the contacts changed the run", dimension, law))
  end
end
print("record contacts same run ok")
