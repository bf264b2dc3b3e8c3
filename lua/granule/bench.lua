-- granule.bench: the dense shaken 3D box the benchmarks share
-- (tools/bench/box3d_compare.lua, decomposition_numbers.lua, scaling.lua):
-- spheres in a square box with four side walls on a floor that shakes
-- vertically, z(t) = A (1 - cos 2 pi f t) (at rest at the bottom of its stroke
-- at t = 0, as LAMMPS's `wiggle` moves a wall), linear contacts with friction,
-- gravity.
--
--   local bench = require "granule.bench"
--   local sim = bench.shaken_box { per_side = 50, time_step = 1.5e-6 }
--   bench.fill_lattice(sim, { per_side = 50, layers = 40 })
-- Scenes that let -D change the box declare its options with bench.parameters
-- and pass them on with bench.options (tools/bench/box3d_compare.lua); timed
-- scenes report with bench.stage_seconds and bench.result_line.
local bench = {}

local defaults = {
  per_side = 50,          -- spheres per side of the box
  radius = 1e-3,          -- m
  density = 2500,         -- kg/m^3
  k_normal = 1e4,         -- N/m
  restitution = 0.5,
  friction = 0.5,
  amplitude = 0.1e-3,     -- m, of the floor
  frequency = 50,         -- Hz, of the floor
  time_step = 1.5e-6,     -- s
  gap = 0,                -- m, between neighbours on the starting lattice (0: touching)
  model = "linear",       -- linear (k_normal) | walton_braun (k_load = k_normal) | hertz_mindlin (young, poisson; restitution calibrated)
  young = 5e7,            -- Pa, hertz_mindlin: spheres and walls alike (a soft glass: dt as linear)
  poisson = 0.25,
}

local units = { radius = "m", density = "kg/m^3", k_normal = "N/m", amplitude = "m",
                frequency = "Hz", time_step = "s", gap = "m", young = "Pa" }

-- The box's options as declarations for a scene's parameters{...} (the
-- defaults and units above), with the scene's own `extra` ones added:
--   local p = parameters(bench.parameters { steps = { default = 1000 } })
function bench.parameters(extra)
  local specs = {}
  for k, v in pairs(defaults) do specs[k] = { default = v, unit = units[k] } end
  for k, v in pairs(extra or {}) do specs[k] = v end
  return specs
end

-- The box's options out of a scene's parameters: the keys shaken_box knows.
--   local sim = bench.shaken_box(bench.options(p))
function bench.options(p)
  local o = {}
  for k in pairs(defaults) do o[k] = p[k] end
  return o
end

local function with_defaults(o)
  local p = {}
  for k, v in pairs(defaults) do p[k] = v end
  for k, v in pairs(o or {}) do
    if defaults[k] == nil and k ~= "layers" then error("granule.bench: unknown option '" .. k .. "'", 3) end
    p[k] = v
  end
  return p
end

-- A simulation with the box's materials, contacts, walls, gravity and the
-- shaking floor (its velocity set every step); no particles yet.
function bench.shaken_box(options)
  local p = with_defaults(options)
  local side = p.per_side * (2 * p.radius + p.gap)
  local sim = simulation { dimension = 3, time_step = p.time_step }
  local hertz = p.model == "hertz_mindlin"
  if not hertz and p.model ~= "linear" and p.model ~= "walton_braun" then
    error("granule.bench: model = '" .. tostring(p.model) .. "' is not linear, walton_braun or hertz_mindlin", 2)
  end
  -- Hertz: one E and nu for spheres and walls, as LAMMPS's granular walls assume.
  local elastic = hertz and { young = p.young, poisson = p.poisson } or {}
  sim:material { name = "glass", density = p.density, young = elastic.young, poisson = elastic.poisson }
  sim:material { name = "steel", density = 7800, young = elastic.young, poisson = elastic.poisson }
  for _, other in ipairs { "glass", "steel" } do
    if hertz then
      sim:contact { "glass", other, model = "hertz_mindlin", restitution = p.restitution, friction = p.friction }
    elseif p.model == "walton_braun" then  -- Granule only (no peer has it): k_load = k_normal
      sim:contact { "glass", other, model = "walton_braun", k_load = p.k_normal, restitution = p.restitution,
                    friction = p.friction }
    else
      sim:contact { "glass", other, model = "linear", k_normal = p.k_normal, restitution = p.restitution,
                    friction = p.friction }
    end
  end
  sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "steel" }
  sim:wall_plane { name = "x_low", point = { 0, 0, 0 }, normal = { 1, 0, 0 }, material = "steel" }
  sim:wall_plane { name = "x_high", point = { side, 0, 0 }, normal = { -1, 0, 0 }, material = "steel" }
  sim:wall_plane { name = "y_low", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "steel" }
  sim:wall_plane { name = "y_high", point = { 0, side, 0 }, normal = { 0, -1, 0 }, material = "steel" }
  sim:gravity { 0, 0, -9.81 }
  -- z = A (1 - cos wt), v = A w sin wt: the phase of LAMMPS's `fix wall/gran
  -- ... wiggle` and of the LIGGGHTS deck's `viblin ... phase pi`
  -- (tools/bench/), so a state saved after whole periods restarts in all three
  -- programs with the floor at rest where the bed rests on it.
  local omega = 2 * math.pi * p.frequency
  sim:every { steps = 1, function(s)
    s:set_wall("floor", { velocity = { 0, 0, p.amplitude * omega * math.sin(omega * s:time()) } })
  end }
  return sim
end

-- per_side^2 x layers spheres on a cubic lattice. With gap = 0 the lattice
-- touches (a dense column from the first step), jittered a little to break its
-- symmetry. With a gap each sphere is moved off its site by up to 0.45 gap
-- along each axis (pseudo-random, the same on every run; no two overlap), so
-- the loose lattice collapses under gravity into a disordered packing whose
-- contacts carry the weight.
function bench.fill_lattice(sim, options)
  local p = with_defaults(options)
  assert(p.layers, "granule.bench.fill_lattice: give layers")
  local r, spacing, k = p.radius, 2 * p.radius + p.gap, 0
  local function hash(x) -- in [-1, 1)
    local f = math.sin(x) * 43758.5453
    return 2 * (f - math.floor(f)) - 1
  end
  for layer = 0, p.layers - 1 do
    for iy = 0, p.per_side - 1 do
      for ix = 0, p.per_side - 1 do
        k = k + 1
        local x, y, z = (ix + 0.5) * spacing, (iy + 0.5) * spacing, (layer + 0.5) * spacing
        if p.gap > 0 then
          local a = 0.45 * p.gap
          x, y, z = x + a * hash(k * 12.9898), y + a * hash(k * 78.233), z + a * hash(k * 37.719)
        else
          local jitter = 0.005 * r * math.sin(k * 12.9898)
          x, y = x + jitter, y - jitter
        end
        sim:add_particle { position = { x, y, z }, radius = r, material = "glass" }
      end
    end
  end
end

-- The stage seconds of a timed window: sim:timings() after it less `before`
-- (sim:timings() taken at its start), under the names compare.py's CSV uses.
-- contacts_s holds walls_s and sums_s (the wall contacts and, with more than
-- one thread, keeping each particle's sum in slot order); pair_wait_s is in
-- thread-seconds (the pair loop's threads waiting at its barrier).
function bench.stage_seconds(sim, before)
  local now = sim:timings()
  local function d(k) return now[k] - before[k] end
  return {
    neighbour_s = d "neighbor", contacts_s = d "force", walls_s = d "walls", sums_s = d "scatter",
    diagnostics_s = d "diagnostics", integrate_s = d "integrate", hooks_s = d "hooks",
    pair_wait_s = d "pair_wait",
  }
end

-- The order of the result line's fields (compare.py reads them by name).
local line_fields = {
  "model", "particles", "steps", "wall_s", "particle_steps_per_s", "mean_contacts", "mean_pair_contacts",
  "mean_kinetic_energy", "neighbour_s", "contacts_s", "walls_s", "sums_s", "diagnostics_s", "integrate_s", "hooks_s",
  "pair_wait_s", "list_rebuilds", "thread_rebalances", "mean_candidates_visited", "list_prunes",
}

-- The one line a timed bench scene prints on stdout for tools/bench/compare.py:
-- "granule key=value ..." with the fields above (strings as given, integers
-- as integers, other numbers to 6 significant digits; a missing field is left
-- out).
function bench.result_line(fields)
  local parts = { "granule" }
  for _, k in ipairs(line_fields) do
    local v = fields[k]
    if type(v) == "number" then
      v = math.type(v) == "integer" and string.format("%d", v) or string.format("%.6g", v)
    end
    if v ~= nil then parts[#parts + 1] = k .. "=" .. tostring(v) end
  end
  return table.concat(parts, " ")
end

-- Refuses a CSV file `path` that starts with a header other than `columns`'
-- (call it before a long run, so that the run is not lost at its end).
function bench.check_csv(path, columns, level)
  local header = table.concat(columns, ",")
  local f = io.open(path, "r")
  local first = f and f:read("l")
  if f then f:close() end
  if first and first ~= header then
    error(string.format("%s: its columns are not %s...: name another file", path, header:sub(1, 40)),
          level or 2)
  end
  return first ~= nil
end

-- Appends `row` (a table keyed by the names in `columns`) to the CSV file
-- `path`, writing the header first when the file is new or empty (a file with
-- another header is refused). Numbers as result_line writes them; an absent
-- value is an empty field.
function bench.append_csv(path, columns, row)
  local has_header = bench.check_csv(path, columns, 3)
  local out, err = io.open(path, "a")
  if not out then error("cannot write " .. tostring(err), 2) end
  if not has_header then out:write(table.concat(columns, ","), "\n") end
  local fields = {}
  for k, name in ipairs(columns) do
    local v = row[name]
    if type(v) == "number" then
      v = math.type(v) == "integer" and string.format("%d", v) or string.format("%.6g", v)
    end
    v = v == nil and "" or tostring(v)
    if v:find('[,"\n]') then v = '"' .. v:gsub('"', '""') .. '"' end
    fields[k] = v
  end
  out:write(table.concat(fields, ","), "\n")
  out:close()
end

-- The stage columns of bench.stage_seconds, in CSV order.
bench.stage_columns = { "neighbour_s", "contacts_s", "walls_s", "sums_s", "diagnostics_s", "integrate_s",
                        "hooks_s", "pair_wait_s" }

return bench
