-- granule.agglomerate_tests: the three breakage tests of dissertation
-- chapter 7 on a prepared agglomerate (granule.agglomerate, 7.3):
--
--   host        normal impact with a host particle, both moving toward each
--               other at v (7.5, Figs. 7.11-7.23)
--   wall        normal impact on a stationary wall at v (7.6, Figs. 7.24-7.30)
--   compression diametrical compression between a fixed and a moving wall
--               until 10 % strain (7.7, Figs. 7.31-7.36)
--
--   local tests = require "granule.agglomerate_tests"
--   local sim = simulation { dimension = 2, record_contacts = true }
--   sim:output {}
--   local result = tests.run(sim, "wall", { file = "agglomerate_2d_g1.h5", velocity = 0.5 })
--
-- A test (1) loads the agglomerate from the last snapshot of a preparation's
-- output with the contact histories saved beside it (a file without them
-- loses its tangential forces, and the agglomerate first settles again with
-- damping: option `settle`); (2) places the
-- target `gap` below it (along -y) and gives the velocities; (3) samples the
-- breakage (sim:breakage, 7.4) every `sample_every` steps into the series
-- /breakage and watches the target's contact force every `contact_every`
-- steps; (4) stops when the impact is over (compression: the strain is
-- reached), no bond has broken for `steady_time` and the agglomerate's mean
-- kinetic energy over that time is within `ke_tolerance` of its mean over the
-- `steady_time` before, or at `max_duration` (the result says which); (5) writes the final fragment labels to the series
-- /clusters (id, label, fragment mass fraction; label 1 = the largest
-- fragment) and the numbers to /results.
--
-- Bonded (option `bonds`, a table of parallel-bond parameters, {} for the
-- defaults of tests.bond_parameters): the primaries' law has no adhesion
-- (surface_energy 0), the agglomerate is loaded without contact histories,
-- dilated about its centre until no two primaries overlap (below) and every
-- pair that touched is bonded (sim:bond, Potyondy and Cundall 2004), so only
-- the bonds hold it. Damage is then the broken parallel bonds over those made
-- and fragments are the clusters of the intact ones (both graphs of /breakage);
-- /breakage and the results also give parallel_bonds_broken and
-- parallel_damage_ratio.
local granule = require "granule"
local agglomerate = require "granule.agglomerate"

local tests = {}

tests.defaults = {
  file = "",                        -- HDF5 output of scenarios/agglomerate_prepare.lua
  snapshot = -1,                    -- which snapshot of it (-1: the last)
  material = "alumina",             -- the primaries' material name in that file
  density = agglomerate.alumina.density,
  young = agglomerate.alumina.young,
  poisson = agglomerate.alumina.poisson,
  friction = -1,                    -- mu between primaries; -1: the prepared file's (its /results)
  surface_energy = -1,              -- Gamma between primaries [J/m^2]; -1: the prepared file's (7.5.2: 1.0 and 2.0)
  other_surface_energy = false,     -- true: a surface_energy other than the file's is taken, not refused
  velocity = 0.1,                   -- m/s: impact velocity (host: of each body) or wall speed
  gap = 20e-9,                      -- m: initial distance to the target ("very small", 7.4)
  settle = "auto",                  -- "auto": settle only without saved contact histories; "always"; "never"
  settle_damping_rate = 1e6,        -- 1/s: damping while the loaded agglomerate settles
  settle_rest_speed = 1e-4,         -- m/s: settled when the internal rms speed is below this
  settle_steady_time = 1e-6,        -- s: ... with the contact count unchanged this long
  settle_max_duration = 40e-6,      -- s: cap of the settling stage
  damping_every = 10,               -- steps between velocity scalings while settling
  sample_every = 100,               -- steps between breakage samples
  contact_every = 20,               -- steps between checks of the target's force
  steady_time = 5e-6,               -- s: window of the end criterion
  ke_tolerance = 0.02,              -- relative change of the mean kinetic energy between two windows
  max_duration = 300e-6,            -- s: cap of the test (safety net)
  host_diameter = agglomerate.pmma.diameter,
  host_density = agglomerate.pmma.density,
  host_young = agglomerate.pmma.young,
  host_poisson = agglomerate.pmma.poisson,
  host_friction = agglomerate.pmma.friction,
  host_surface_energy = 0,          -- J/m^2 between host and primaries (not given in 7.5)
  wall_young = agglomerate.target.young,
  wall_poisson = agglomerate.target.poisson,
  wall_friction = agglomerate.target.friction,
  wall_surface_energy = 0,          -- J/m^2 between wall and primaries (not given in 7.6)
  strain = 0.10,                    -- compression: wall travel / agglomerate height (7.7)
  large = 0.10,                     -- fragment classes, fractions of the initial mass (7.4)
  debris = 0.025,
  fines = 0.002,
  quiet = false,
  bonds = false,                    -- false: JKR; a table: bonded (tests.bond_parameters)
}

-- The law between primaries where neither the test nor the prepared file
-- gives one (a file not written by scenarios/agglomerate_prepare.lua).
tests.fallback_law = { friction = agglomerate.alumina.friction, surface_energy = 1.0 }

--- The law between primaries, from the file the agglomerate was prepared in
--- (`prepared`: its /results) where the test leaves it at -1. Its contact
--- histories and the balance of its adhesive contacts belong to the surface
--- energy it was prepared with: a lower one leaves contacts in tension past
--- their new pull-off, which part before the test begins, a higher one pulls
--- them tighter; so a different one is refused (not for bonds, which part the
--- contacts and take Gamma for their strength only). Friction may differ: a
--- contact whose tangential spring is past the new cap slips at the first step.
function tests.prepared_law(sim, o, prepared, bonded, context)
  local declared = { friction = o.friction >= 0 and o.friction or tests.fallback_law.friction,
                     surface_energy = o.surface_energy >= 0 and o.surface_energy or tests.fallback_law.surface_energy }
  local gamma = prepared.surface_energy
  if (o.surface_energy < 0 and gamma == nil) or (o.friction < 0 and prepared.friction == nil) then
    io.stderr:write(string.format("warning: %s: %s reports no surface_energy or friction in its /results "
      .. "(not written by scenarios/agglomerate_prepare.lua?): the primaries' law is taken as "
      .. "surface_energy = %g J/m^2, friction = %g where not given\n", context, o.file,
      tests.fallback_law.surface_energy, tests.fallback_law.friction))
  end
  -- Bonded, the contacts are parted and Gamma only sets the bonds' strength: any may be tested.
  if o.surface_energy >= 0 and gamma and o.surface_energy ~= gamma and not o.other_surface_energy
      and not bonded then
    error(string.format("%s: surface_energy = %g J/m^2, but %s was prepared with %g J/m^2; its contacts "
      .. "balance at that value only, and another starts it out of equilibrium: leave surface_energy "
      .. "out (-1) to test at the prepared value, prepare it with %g "
      .. "(scenarios/agglomerate_prepare.lua -D surface_energy=%g), or give other_surface_energy = true",
      context, o.surface_energy, o.file, gamma, o.surface_energy, o.surface_energy), 3)
  end
  if o.surface_energy < 0 then o.surface_energy = gamma or tests.fallback_law.surface_energy end
  if o.friction < 0 then o.friction = prepared.friction or tests.fallback_law.friction end
  if o.friction ~= declared.friction or o.surface_energy ~= declared.surface_energy then
    sim:set_contact(o.material, o.material, { friction = o.friction,
                                              surface_energy = bonded and 0 or o.surface_energy })
  end
end

local rules = {
  density = { "positive", "kg/m^3" }, young = { "positive", "Pa" }, poisson = { "non_negative" },
  velocity = { "positive", "m/s" },
  gap = { "non_negative", "m" }, settle_damping_rate = { "positive", "1/s" },
  settle_rest_speed = { "positive", "m/s" }, settle_steady_time = { "non_negative", "s" },
  settle_max_duration = { "positive", "s" }, damping_every = { "count" }, sample_every = { "count" },
  contact_every = { "count" }, steady_time = { "positive", "s" }, ke_tolerance = { "positive" },
  max_duration = { "positive", "s" }, host_diameter = { "positive", "m" }, host_density = { "positive", "kg/m^3" },
  host_young = { "positive", "Pa" }, host_poisson = { "non_negative" }, host_friction = { "non_negative" },
  host_surface_energy = { "non_negative", "J/m^2" }, wall_young = { "positive", "Pa" },
  wall_poisson = { "non_negative" }, wall_friction = { "non_negative" },
  wall_surface_energy = { "non_negative", "J/m^2" }, strain = { "positive" }, large = { "positive" },
  debris = { "positive" }, fines = { "positive" },
}

-- The parallel bonds that stand for the JKR contacts of an agglomerate with
-- surface energy Gamma between primaries of mean radius r (R* = r / 2, E* =
-- E / (2 (1 - nu^2)), bond radius R_b = lambda r), for any parameter left 0:
--   tensile_strength: the bond's tensile force pi R_b^2 sigma_c equals the JKR
--     pull-off force 1.5 pi Gamma R* (Johnson, Kendall and Roberts 1971), so a
--     pair parts under the same pull in both agglomerates;
--   normal_stiffness: k_n pi R_b^2 equals the JKR contact's stiffness at its
--     zero-load equilibrium, dF/d(delta) = 1.2 E* a_0 with
--     a_0 = (9 pi Gamma R*^2 / (2 E*))^(1/3) (from F(a), delta(a) of JKR), so
--     the agglomerate rings at about the same frequency;
--   shear_stiffness: k_n 2 (1 - nu) / (2 - nu), Mindlin's ratio of the
--     tangential to the normal stiffness of an elastic contact;
--   shear_strength: the tensile strength (Potyondy and Cundall's usual choice);
--   radius_multiplier lambda = 1: the cement disk spans the smaller primary (their
--     Table 1 value).
tests.bond_defaults = { normal_stiffness = 0, shear_stiffness = 0, tensile_strength = 0, shear_strength = 0,
                        radius_multiplier = 1 }

--- The parallel-bond parameters for primaries of mean radius `radius` with
--- young, poisson and surface_energy; `given` overrides (0 = derived).
function tests.bond_parameters(given, radius, young, poisson, surface_energy, context)
  local b = agglomerate.options(given, tests.bond_defaults, context .. ": bonds")
  agglomerate.check(b, { normal_stiffness = { "non_negative", "Pa/m" }, shear_stiffness = { "non_negative", "Pa/m" },
    tensile_strength = { "non_negative", "Pa" }, shear_strength = { "non_negative", "Pa" },
    radius_multiplier = { "positive" } }, context .. ": bonds")
  local e_star = young / (2 * (1 - poisson ^ 2))
  local r_star = radius / 2
  local area = math.pi * (b.radius_multiplier * radius) ^ 2
  if b.tensile_strength == 0 then
    if surface_energy <= 0 then
      error(context .. ": bonds.tensile_strength is needed when surface_energy is 0 (it derives from it)", 3)
    end
    b.tensile_strength = 1.5 * math.pi * surface_energy * r_star / area
  end
  if b.normal_stiffness == 0 then
    local a0 = (9 * math.pi * surface_energy * r_star ^ 2 / (2 * e_star)) ^ (1 / 3)
    if a0 <= 0 then error(context .. ": bonds.normal_stiffness is needed when surface_energy is 0", 3) end
    b.normal_stiffness = 1.2 * e_star * a0 / area
  end
  if b.shear_stiffness == 0 then b.shear_stiffness = b.normal_stiffness * 2 * (1 - poisson) / (2 - poisson) end
  if b.shear_strength == 0 then b.shear_strength = b.tensile_strength end
  return b
end

-- Moves the particles `ids` away from their centre of mass by one factor, the
-- smallest that leaves no two of them overlapping, and returns the pairs that
-- overlapped and the largest gap between two of them afterwards. Bonds made
-- on the overlapped packing would carry, once the adhesion is off, the elastic
-- repulsion of every JKR contact at its equilibrium overlap (Hertz at
-- delta_0 = a_0^2 / (3 R*): 0.77 of the pull-off force) from the start; the
-- dilation (a strain of about delta_0 / (2 r), 2e-4 for 5 um alumina) leaves every
-- pair force-free.
-- The overlapping pairs are found on a uniform grid of cells 2 r_max wide (a
-- pair can only overlap if its centres are closer than that), so each primary
-- is compared with those in its own and the neighbouring cells: linear in the
-- number of primaries, where comparing every pair is quadratic. The cells
-- are 1e-6 wider than 2 r_max and counted from the packing's lowest corner so
-- that rounding in a cell index cannot put two overlapping centres two cells
-- apart. Each pair is tested by the same
-- arithmetic as an all-pairs search, and the factor and widest gap are maxima
-- over the pairs, so the result does not depend on the order they are found in.
local function dilate_apart(sim, ids, center)
  local n = #ids
  local x, r, r_max = {}, {}, 0
  for k, id in ipairs(ids) do
    local particle = sim:particle(id)
    x[k], r[k] = particle.position, particle.radius
    r_max = math.max(r_max, r[k])
  end
  local d = #x[1]
  local low = {}
  for j = 1, d do
    low[j] = math.huge
    for k = 1, n do low[j] = math.min(low[j], x[k][j]) end
  end
  local size = 2 * r_max * (1 + 1e-6)
  -- grid[i][j] (2D) or grid[i][j][k] (3D): the primaries in that cell, in order.
  local cell, grid = {}, {}
  for a = 1, n do
    local c = {}
    for j = 1, d do c[j] = math.floor((x[a][j] - low[j]) / size) end
    cell[a] = c
    local level = grid
    for j = 1, d - 1 do
      level[c[j]] = level[c[j]] or {}
      level = level[c[j]]
    end
    level[c[d]] = level[c[d]] or {}
    table.insert(level[c[d]], a)
  end
  local pairs_touching, factor = {}, 1
  local function test(a, members)
    local xa = x[a]
    for _, b in ipairs(members) do
      if b > a then
        local xb, s = x[b], 0
        for k = 1, d do s = s + (xa[k] - xb[k]) ^ 2 end
        local distance, contact = math.sqrt(s), r[a] + r[b]
        if distance < contact then
          pairs_touching[#pairs_touching + 1] = { a, b, distance, contact }
          factor = math.max(factor, contact / distance)
        end
      end
    end
  end
  for a = 1, n do
    local c = cell[a]
    for i = c[1] - 1, c[1] + 1 do
      local row = grid[i]
      if row then
        for j = c[2] - 1, c[2] + 1 do
          local column = row[j]
          if column and d == 2 then
            test(a, column)
          elseif column then
            for k = c[3] - 1, c[3] + 1 do
              if column[k] then test(a, column[k]) end
            end
          end
        end
      end
    end
  end
  factor = factor * (1 + 1e-9)
  for k, id in ipairs(ids) do
    local p = {}
    for j = 1, d do p[j] = center[j] + factor * (x[k][j] - center[j]) end
    sim:set_position(id, p)
  end
  local widest = 0
  for _, t in ipairs(pairs_touching) do widest = math.max(widest, factor * t[3] - t[4]) end
  return #pairs_touching, widest, factor
end

tests.kinds = { host = "normal impact with a host particle (7.5)", wall = "normal impact on a wall (7.6)",
                compression = "diametrical compression (7.7)" }

-- Columns of /breakage. Fragments are clusters of the contact graph (7.4); the
-- *_bonds columns use the graph of the initial bonds that survive instead,
-- which keeps apart pieces that new contacts join (between two walls).
tests.series_columns = { "time", "damage_ratio", "debris_ratio", "fines_ratio", "largest_fraction", "fragments",
                         "large", "medium", "small", "broken_bonds", "debris_ratio_bonds",
                         "largest_fraction_bonds", "fragments_bonds", "kinetic_energy", "target_force",
                         "in_contact", "wall_travel", "debris_ratio_by_size", "singles_ratio", "bonded_debris_ratio",
                         "debris_ratio_by_size_bonds", "bonded_debris_ratio_bonds", "approach_speed" }
-- Their units, column by column (counts and ratios '-').
local series_units = { time = "s", kinetic_energy = "J", target_force = "N", wall_travel = "m",
                       approach_speed = "m/s" }

-- Kinetic energy of one particle (translation + rotation, I = m d^2 / 10, SPEC 2).
local function particle_kinetic_energy(p)
  local v2, w2 = 0, 0
  for _, vk in ipairs(p.velocity) do v2 = v2 + vk * vk end
  if type(p.spin) == "number" then w2 = p.spin * p.spin else for _, wk in ipairs(p.spin) do w2 = w2 + wk * wk end end
  return 0.5 * p.mass * v2 + 0.5 * (0.4 * p.mass * p.radius ^ 2) * w2
end

local function norm(v)
  local s = 0
  for _, x in ipairs(v) do s = s + x * x end
  return math.sqrt(s)
end

-- The platens may not come closer than the largest primary's diameter: squeezed
-- past it, every primary is pressed into both and thrown out sideways.
local function check_strain(sim, ids, o, context)
  local shape = agglomerate.geometry(sim, ids)
  local height = shape.high[2] - shape.low[2]
  local largest = 0
  for _, id in ipairs(ids) do largest = math.max(largest, sim:particle(id).radius) end
  local most = 1 - 2 * largest / height
  if o.strain > most then
    error(string.format("%s: 'strain' %g would bring the platens closer than the largest primary's "
      .. "diameter %g m (the agglomerate is %g m high): at most %.3g", context, o.strain, 2 * largest,
      height, math.max(0, most)), 3)
  end
end

--- Runs test `kind` ("host", "wall" or "compression") in `sim`, an empty
--- simulation with record_contacts = true and an output. Returns the result
--- table (also written to /results).
function tests.run(sim, kind, given)
  local context = "agglomerate test '" .. tostring(kind) .. "'"
  if not tests.kinds[kind] then
    error(string.format("agglomerate test: unknown kind '%s' (host, wall or compression)", tostring(kind)), 2)
  end
  local o = agglomerate.options(given, tests.defaults, context)
  agglomerate.check(o, rules, context)
  if o.file == "" then
    error(context .. ": 'file' is required: the output of scenarios/agglomerate_prepare.lua", 2)
  end
  if o.strain >= 1 then error(context .. ": 'strain' must be < 1 (a fraction of the height)", 2) end
  if o.settle ~= "auto" and o.settle ~= "always" and o.settle ~= "never" then
    error(context .. ": 'settle' must be \"auto\", \"always\" or \"never\", got " .. tostring(o.settle), 2)
  end
  if #sim:particles() > 0 then error(context .. ": the simulation must hold no particles yet", 2) end
  if o.bonds ~= false and type(o.bonds) ~= "table" then
    error(context .. ": 'bonds' must be false or a table of parallel-bond parameters, got " .. tostring(o.bonds), 2)
  end
  local bonded = type(o.bonds) == "table"
  local d = sim:dimension()
  local clock = os.clock()
  local up = function(s) return agglomerate.axis_vector(d, 2, s) end

  -- (1) The agglomerate with its contact histories, or settled again with
  -- damping where the file has none.
  sim:material { name = o.material, density = o.density, young = o.young, poisson = o.poisson }
  for _, key in ipairs { "friction", "surface_energy" } do
    if o[key] ~= -1 then agglomerate.check({ [key] = o[key] }, { [key] = { "non_negative" } }, context) end
  end
  -- Declared with the values asked for (or the fallbacks), set to the file's once it is read.
  sim:contact { o.material, o.material, model = "thornton_jkr",
                friction = o.friction >= 0 and o.friction or tests.fallback_law.friction,
                surface_energy = bonded and 0 or (o.surface_energy >= 0 and o.surface_energy
                                                  or tests.fallback_law.surface_energy) }
  -- Bonded, the JKR histories are not wanted (the law has no adhesion and the
  -- dilation below parts every contact); otherwise used where the file has them.
  local load = { file = o.file, snapshot = o.snapshot }
  if bonded then load.histories = false end
  local ids, restored, prepared = sim:load_particles(load)
  -- Checked as loaded (before any settling: a long settle need not be waited for) and
  -- again as settled.
  if kind == "compression" then check_strain(sim, ids, o, context) end
  tests.prepared_law(sim, o, prepared, bonded, context)
  local mass = agglomerate.total_mass(sim, ids)
  local bond = nil
  if bonded then
    local radius = 0
    for _, id in ipairs(ids) do radius = radius + sim:particle(id).radius / #ids end
    bond = tests.bond_parameters(o.bonds, radius, o.young, o.poisson, o.surface_energy, context)
    local touching, widest, factor = dilate_apart(sim, ids, agglomerate.geometry(sim, ids).center)
    bond.pairs_touching, bond.dilation = touching, factor - 1
    bond.made = sim:bond { materials = { o.material }, gap = widest + 1e-9 * radius,
                           radius_multiplier = bond.radius_multiplier, normal_stiffness = bond.normal_stiffness,
                           shear_stiffness = bond.shear_stiffness, tensile_strength = bond.tensile_strength,
                           shear_strength = bond.shear_strength }
  end
  sim:run { steps = 1 }
  local bonds_loaded = #sim:bonds { material = o.material }
  local settle = { duration = 0, ended_by = "criterion" }
  -- Bonded, the dilated packing is force-free: nothing to settle.
  if not bonded and (o.settle == "always" or (o.settle == "auto" and restored == 0)) then
    local damping = agglomerate.start_damping(sim, o.material, o.settle_damping_rate, o.damping_every)
    settle = agglomerate.run_stage(sim, "settle after loading", o.settle_max_duration, o.sample_every,
      agglomerate.at_rest(mass, o.settle_rest_speed, o.settle_steady_time), o.quiet)
    sim:remove_hook(damping)
  end
  local shape = agglomerate.geometry(sim, ids)
  local height = shape.high[2] - shape.low[2]
  if kind == "compression" then check_strain(sim, ids, o, context) end

  -- (2) The target, below the agglomerate (along -y), and the velocities.
  local target = {}
  local below = shape.low[2] - o.gap
  if kind == "host" then
    sim:material { name = "host", density = o.host_density, young = o.host_young, poisson = o.host_poisson }
    sim:contact { o.material, "host", model = "thornton_jkr", friction = o.host_friction,
                  surface_energy = o.host_surface_energy }
    -- One host meets no other; its law with itself enters only the time step's rule.
    sim:contact { "host", "host", model = "thornton_jkr", friction = o.host_friction, surface_energy = 0 }
    local position = {}
    for k = 1, d do position[k] = shape.center[k] end
    position[2] = below - o.host_diameter / 2
    -- 7.5: "two elements have the same incoming velocity".
    target.host = sim:add_particle { position = position, velocity = up(o.velocity), radius = o.host_diameter / 2,
                                     material = "host" }
    target.force = function(s) return norm(s:particle(target.host).force) end
  else
    sim:material { name = "wall", young = o.wall_young, poisson = o.wall_poisson }
    sim:contact { o.material, "wall", model = "thornton_jkr", friction = o.wall_friction,
                  surface_energy = o.wall_surface_energy }
    local point = {}
    for k = 1, d do point[k] = shape.center[k] end
    point[2] = below
    sim:wall_plane { name = "bottom", point = point, normal = up(1), material = "wall" }
    target.force = function(s) return norm(s:wall("bottom").force) end
    if kind == "compression" then
      local top = {}
      for k = 1, d do top[k] = shape.center[k] end
      top[2] = shape.high[2] + o.gap
      sim:wall_plane { name = "top", point = top, normal = up(-1), material = "wall", velocity = up(-o.velocity) }
      target.force = function(s) return 0.5 * (norm(s:wall("bottom").force) + norm(s:wall("top").force)) end
    end
  end
  if kind ~= "compression" then
    for _, id in ipairs(ids) do sim:set_velocity(id, up(-o.velocity)) end
  end

  -- (3) Watching the target and sampling the breakage.
  local initial_bonds = sim:bonds { material = o.material }
  local classes = { large = o.large, debris = o.debris, fines = o.fines }
  -- (Bonded, the parallel bonds hold it and its damage is theirs: the contacts'
  -- histories were not loaded, and the dilation left none touching.)
  if #initial_bonds == 0 and not bonded then
    io.stderr:write(string.format("warning: %s: %s holds no contacts between its primaries (prepared "
      .. "with surface_energy = 0?): they are loose, and the damage ratio (broken / initial bonds) "
      .. "reads 0\n", context, o.file))
  end
  -- Debris is under `debris` of the primaries (by size) or of the mass: with
  -- few primaries not even one primary is, and both debris ratios read 0.
  do
    local volume, smallest = 0, math.huge
    for _, id in ipairs(ids) do
      local v = sim:particle(id).radius ^ d
      volume, smallest = volume + v, math.min(smallest, v)
    end
    if #ids * o.debris <= 1 and smallest / volume >= o.debris then
      io.stderr:write(string.format("warning: %s: with %d primaries one primary is %.3g of the "
        .. "agglomerate's mass, at least debris = %g, so neither debris rule (size or mass) can count "
        .. "a fragment as debris: the debris ratios read 0; read the fragments and the largest "
        .. "fragment\n", context, #ids, smallest / volume, o.debris))
    end
  end
  local t0 = sim:time()
  -- The impact is the first contact episode; later touches (a fragment or a
  -- vibrating face meeting the target again) are counted, not added to it.
  local contact = { first = nil, ended = nil, last = nil, now = false, episodes = 0, peak_force = 0 }
  local travel_target = o.strain * height
  local strained_at = nil
  local function wall_travel(s)
    if kind ~= "compression" then return 0 end
    return math.min(travel_target, o.velocity * (s:time() - t0))
  end
  local watch = sim:every { steps = o.contact_every, name = "target contact", function(s)
    local f = target.force(s)
    local touching = f > 0
    if touching and not contact.now then contact.episodes = contact.episodes + 1 end
    contact.now = touching
    contact.peak_force = math.max(contact.peak_force, f)
    if touching then
      contact.first = contact.first or s:time()
      contact.last = s:time()
    elseif contact.first and not contact.ended then
      contact.ended = s:time()
    end
    if kind == "compression" and not strained_at and o.velocity * (s:time() - t0) >= travel_target then
      -- 7.7: the moving wall stops at the target strain.
      strained_at = s:time()
      s:set_wall("top", { velocity = up(0) })
    end
  end }
  local function agglomerate_kinetic_energy(s)
    local e = s:stats().kinetic_energy
    if target.host then e = e - particle_kinetic_energy(s:particle(target.host)) end
    return e
  end
  local columns = {}
  for k, c in ipairs(tests.series_columns) do columns[k] = c end
  if bonded then
    columns[#columns + 1] = "parallel_bonds_broken"
    columns[#columns + 1] = "parallel_damage_ratio"
  end
  local units = {}
  for k, c in ipairs(columns) do units[k] = series_units[c] or "-" end
  sim:series("breakage", columns, units)
  local history = {}
  -- The damage counts a pair that parted and touches again as intact, so it can
  -- fall after its peak: the largest sample is reported beside the last.
  local peak_damage = 0
  local function measure(s, graph, labels)
    if bonded then graph = "parallel_bonds" end
    local b = s:breakage { initial_bonds = initial_bonds, material = o.material, initial_mass = mass, graph = graph,
                        labels = labels, large = classes.large, debris = classes.debris, fines = classes.fines,
                        initial_count = #ids }
    if bonded then b.damage_ratio, b.broken_bonds = b.parallel_damage_ratio, b.parallel_bonds_broken end
    return b
  end
  -- The speed at which agglomerate and target close (> 0) or part (< 0) along
  -- y: from the momentum of the agglomerate's centre of mass (the total less
  -- the host's), for the impact times of 7.5.1.
  local function approach_speed(s)
    local p = s:stats().momentum[2]
    if target.host then
      local h = s:particle(target.host)
      p = p - h.mass * h.velocity[2]
      return h.velocity[2] - p / mass
    end
    return -p / mass
  end
  local function sample(s)
    local b, kept = measure(s, "contacts"), measure(s, "surviving_bonds")
    local row = { time = s:time() - t0, broken = b.broken_bonds, kinetic_energy = agglomerate_kinetic_energy(s) }
    peak_damage = math.max(peak_damage, b.damage_ratio)
    history[#history + 1] = row
    local values = { row.time, b.damage_ratio, b.debris_ratio, b.fines_ratio, b.largest_fraction, b.fragments,
                           b.large, b.medium, b.small, b.broken_bonds, kept.debris_ratio, kept.largest_fraction,
                           kept.fragments, row.kinetic_energy, target.force(s), contact.now and 1 or 0,
                           wall_travel(s), b.debris_ratio_by_size, b.singles_ratio, b.bonded_debris_ratio,
                           kept.debris_ratio_by_size, kept.bonded_debris_ratio, approach_speed(s) }
    if bonded then
      values[#values + 1] = b.parallel_bonds_broken
      values[#values + 1] = b.parallel_damage_ratio
    end
    s:append("breakage", values)
  end
  sample(sim)
  local sampler = sim:every { steps = o.sample_every, name = "breakage sample", sample }

  -- (4) The end: impact over, no bond broken and the kinetic energy steady
  -- over the last steady_time (7.5: "zero rate of bond breakage and a constant
  -- kinetic energy").
  -- Steady: no bond broken in the last steady_time, and the mean kinetic energy
  -- of that window within ke_tolerance of the mean of the window before. Means,
  -- not extremes: the undamped elastic ringing of the bonds makes the kinetic
  -- energy flicker by a few per cent about a constant mean for ever.
  local function steady()
    local last = history[#history]
    if not last or last.time < 2 * o.steady_time then return false end
    local sums, counts = { 0, 0 }, { 0, 0 }
    for k = #history, 1, -1 do
      local h = history[k]
      local window = h.time >= last.time - o.steady_time and 1 or 2
      if h.time < last.time - 2 * o.steady_time then break end
      if window == 1 and h.broken ~= last.broken then return false end
      sums[window], counts[window] = sums[window] + h.kinetic_energy, counts[window] + 1
    end
    if counts[1] < 2 or counts[2] < 2 then return false end
    local recent, before = sums[1] / counts[1], sums[2] / counts[2]
    return math.abs(recent - before) <= o.ke_tolerance * recent
  end
  local function over()
    if kind == "compression" then return strained_at ~= nil end
    return contact.ended ~= nil and not contact.now
  end
  local r = sim:run { duration = o.max_duration, check_every = o.sample_every,
                      stop_when = function() return over() and steady() end }
  sim:remove_hook(watch)
  sim:remove_hook(sampler)

  -- (5) The final state: fragments with labels, results.
  local b, kept = measure(sim, "contacts", true), measure(sim, "surviving_bonds", true)
  sim:series("clusters", { "id", "label", "mass_fraction", "label_bonds", "mass_fraction_bonds" })
  local sorted = {}
  for _, id in ipairs(ids) do sorted[#sorted + 1] = id end
  table.sort(sorted)
  for _, id in ipairs(sorted) do
    local label, label_bonds = b.labels[id], kept.labels[id]
    sim:append("clusters", { id, label, b.mass_fractions[label], label_bonds, kept.mass_fractions[label_bonds] })
  end
  sim:snapshot()
  local result = {
    kind = kind, dimension = d, velocity = o.velocity, surface_energy = o.surface_energy, primaries = #ids,
    diameter = shape.diameter, height = height, initial_bonds = #initial_bonds, bonds_loaded = bonds_loaded,
    histories_restored = restored,
    settle_duration = settle.duration, settled_by_criterion = settle.ended_by == "criterion" and 1 or 0,
    damage_ratio = b.damage_ratio, peak_damage_ratio = math.max(peak_damage, b.damage_ratio),
    debris_ratio = b.debris_ratio, fines_ratio = b.fines_ratio,
    largest_fraction = b.largest_fraction, fragments = b.fragments, large = b.large, medium = b.medium,
    small = b.small, fines = b.fines, singles = b.singles, broken_bonds = b.broken_bonds,
    debris_ratio_bonds = kept.debris_ratio, largest_fraction_bonds = kept.largest_fraction,
    fragments_bonds = kept.fragments, debris_ratio_by_size = b.debris_ratio_by_size, singles_ratio = b.singles_ratio,
    bonded_debris_ratio = b.bonded_debris_ratio, bonded_debris = b.bonded_debris,
    debris_ratio_by_size_bonds = kept.debris_ratio_by_size, singles_ratio_bonds = kept.singles_ratio,
    bonded_debris_ratio_bonds = kept.bonded_debris_ratio,
    contact_start = contact.first and contact.first - t0 or -1,
    impact_duration = (contact.first and contact.ended) and contact.ended - contact.first or -1,
    last_contact = contact.last and contact.last - t0 or -1, contact_episodes = contact.episodes,
    peak_force = contact.peak_force, strained_at = strained_at and strained_at - t0 or -1,
    test_duration = sim:time() - t0, steps = r.steps, ended_by_criterion = r.stopped and 1 or 0,
    cpu_time = os.clock() - clock, bonded = bonded and 1 or 0,
  }
  if bonded then
    result.initial_bonds = b.parallel_bonds
    result.parallel_bonds = b.parallel_bonds
    result.parallel_bonds_broken = b.parallel_bonds_broken
    result.parallel_damage_ratio = b.parallel_damage_ratio
    result.pairs_touching, result.dilation = bond.pairs_touching, bond.dilation
    result.bond_normal_stiffness, result.bond_shear_stiffness = bond.normal_stiffness, bond.shear_stiffness
    result.bond_tensile_strength, result.bond_shear_strength = bond.tensile_strength, bond.shear_strength
    result.bond_radius_multiplier = bond.radius_multiplier
  end
  -- Where the walls are at the end (the output's /walls header is written before
  -- the test adds them), for the pictures.
  if kind ~= "host" then result.wall_bottom_y = sim:wall("bottom").point[2] end
  if kind == "compression" then result.wall_top_y = sim:wall("top").point[2] end
  local numbers = {}
  for k, v in pairs(result) do if type(v) == "number" then numbers[k] = v end end
  sim:result(numbers)
  result.ended_by = r.stopped and "criterion" or "cap"
  return result
end

--- One line "key=value ..." of a test result, for logs, tests and studies.
function tests.summary_line(result)
  return granule.summary_line(result, { "kind", "dimension", "velocity", "surface_energy", "primaries",
    "bonded", "initial_bonds", "damage_ratio", "debris_ratio", "largest_fraction", "fragments", "large", "medium", "small",
    "fines", "debris_ratio_bonds", "largest_fraction_bonds", "impact_duration", "contact_episodes", "peak_force",
    "test_duration", "ended_by", "cpu_time" })
end

return tests
