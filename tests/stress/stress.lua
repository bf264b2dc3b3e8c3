-- Shared checks of the stress suite (loaded with dofile beside each case).
-- Every case checks that a hard run stays finite, bounded and physically
-- plausible, or is refused with a message that names the problem.
local S = {}

local function fmt(v) return type(v) == "number" and string.format("%.6g", v) or tostring(v) end

--- S.check(condition, what, ...): raises "what" (formatted with ...) unless condition holds.
function S.check(condition, what, ...)
  if not condition then
    local args = table.pack(...)
    for k = 1, args.n do args[k] = fmt(args[k]) end
    error(string.format(what, table.unpack(args, 1, args.n)), 2)
  end
end

--- S.finite(x): x is a number that is neither NaN nor infinite.
function S.finite(x) return type(x) == "number" and x == x and x ~= math.huge and x ~= -math.huge end

--- S.relative(actual, expected, tolerance, what)
function S.relative(actual, expected, tolerance, what)
  S.check(S.finite(actual) and math.abs(actual - expected) <= tolerance * math.abs(expected),
    "%s: got %s, expected %s (relative tolerance %s)", what, actual, expected, tolerance)
end

--- S.fails(pattern, f, ...): f(...) raises an error containing `pattern` (plain); returns the message.
function S.fails(pattern, f, ...)
  local ok, message = pcall(f, ...)
  S.check(not ok, "expected an error mentioning '%s', but the call succeeded", pattern)
  S.check(tostring(message):find(pattern, 1, true), "expected an error mentioning '%s', got: %s",
    pattern, tostring(message))
  return tostring(message)
end

--- S.all_finite(sim): every particle's position, velocity and spin are finite; returns max speed.
function S.all_finite(sim)
  local vmax = 0
  for _, id in ipairs(sim:particles()) do
    local p = sim:particle(id)
    local spin = type(p.spin) == "table" and p.spin or { p.spin }
    for _, list in ipairs { p.position, p.velocity, spin } do
      for _, x in ipairs(list) do S.check(S.finite(x), "particle %s has a non-finite state", id) end
    end
    local s = 0
    for _, x in ipairs(p.velocity) do s = s + x * x end
    vmax = math.max(vmax, math.sqrt(s))
  end
  return vmax
end

--- S.energy(sim, k_normal, k_tangential): kinetic energy plus the elastic energy stored in the
--- linear springs of the last step's contacts (needs record_contacts = true), J.
function S.energy(sim, k_normal, k_tangential)
  local e = sim:stats().kinetic_energy
  for _, c in ipairs(sim:contacts()) do
    if c.overlap > 0 then e = e + 0.5 * k_normal * c.overlap ^ 2 end
    if k_tangential and k_tangential > 0 then
      local t2 = 0
      for _, x in ipairs(c.tangential_force) do t2 = t2 + x * x end
      e = e + 0.5 * t2 / k_tangential
    end
  end
  return e
end

--- S.sphere_mass(r, density)
function S.sphere_mass(r, density) return 4 / 3 * math.pi * r ^ 3 * density end

--- S.head_on(opts) -> { restitution =, duration =, max_overlap =, steps = }
--- Two equal spheres (or one on a wall, opts.wall = true) meeting head-on at relative speed
--- opts.speed along x; opts.law is the sim:contact table without the material names.
--- opts.dimension (2), radius (0.2e-3 m), density (1200 kg/m^3), steps_per_contact, time_step.
function S.head_on(opts)
  local d = opts.dimension or 2
  local r, rho = opts.radius or 0.2e-3, opts.density or 1200
  local sim = simulation { dimension = d, record_contacts = true, steps_per_contact = opts.steps_per_contact,
                           time_step = opts.time_step }
  sim:material { name = "m", density = rho, young = opts.young or 0, poisson = opts.poisson or 0,
                 surface_energy = opts.surface_energy or 0 }
  sim:material { name = "w", density = 0, young = opts.young or 0, poisson = opts.poisson or 0,
                 surface_energy = opts.surface_energy or 0 }
  for _, other in ipairs { "m", "w" } do
    local law = {}
    for k, v in pairs(opts.law) do law[k] = v end
    law[1], law[2] = "m", other
    sim:contact(law)
  end
  local function v(x, y) if d == 3 then return { x, y or 0, 0 } end return { x, y or 0 } end
  local gap = 0.01 * r
  local a, b
  if opts.wall then
    sim:wall_plane { name = "target", point = v(0), normal = v(-1), material = "w" }
    a = sim:add_particle { position = v(-r - gap), velocity = v(opts.speed), radius = r, material = "m" }
  else
    a = sim:add_particle { position = v(-r - gap / 2), velocity = v(opts.speed / 2), radius = r, material = "m" }
    b = sim:add_particle { position = v(r + gap / 2), velocity = v(-opts.speed / 2), radius = r, material = "m" }
  end
  local seen, ended, steps, max_overlap, min_force = false, false, 0, 0, math.huge
  sim:every { steps = 1, function(s)
    local list = s:contacts()
    if #list == 0 then
      if seen then ended = true end
      return
    end
    seen = true
    if list[1].normal_force > 0 then steps = steps + 1 end
    max_overlap = math.max(max_overlap, list[1].overlap)
    min_force = math.min(min_force, list[1].normal_force)
  end }
  local m = S.sphere_mass(r, rho)
  local limit = opts.max_duration or 1.0
  sim:run { duration = limit, check_every = 1, stop_when = function() return ended end }
  S.check(ended, "the contact did not end within %s s", limit)
  local va = sim:particle(a).velocity[1]
  local vb = b and sim:particle(b).velocity[1] or 0
  S.all_finite(sim)
  return { restitution = (vb - va) / opts.speed, duration = steps * sim:time_step(), max_overlap = max_overlap,
           steps = steps, dt = sim:time_step(), mass = m, sim = sim, min_force = min_force }
end

return S
