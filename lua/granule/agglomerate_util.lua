-- granule.agglomerate_util: the option handling and the random generation
-- (Figs. 7.9-7.10) of the agglomerate protocols (granule.agglomerate, which
-- re-exports every function here). No simulation is touched in this file.
-- Errors are raised at the first caller outside the library (granule.checks).
local raise = require("granule.checks").raise

local agglomerate = {}

-- ---------------------------------------------------------------------------
-- Options: defaults, units, checks
-- ---------------------------------------------------------------------------

-- The nearest of `names` to `word`, for "did you mean" hints: the engine's rule
-- (core/names.cpp), the one every other message of a scene uses.
local nearest = require("granule.checks").nearest

--- Copies `given` over `defaults`; an unknown key is an error naming it and
--- the nearest valid name. `context` starts the message.
function agglomerate.options(given, defaults, context)
  if given ~= nil and type(given) ~= "table" then
    raise(string.format("%s: the options must be a table { name = value, ... }, got a %s", context, type(given)))
  end
  local out = {}
  for k, v in pairs(defaults) do out[k] = v end
  for k, v in pairs(given or {}) do
    if defaults[k] == nil then
      local names = {}
      for name in pairs(defaults) do names[#names + 1] = name end
      table.sort(names)
      local hint = type(k) == "string" and nearest(k, names) or nil
      raise(string.format("%s: unknown option '%s'%s", context, tostring(k),
        hint and string.format(" (did you mean '%s'?)", hint) or ""))
    end
    out[k] = v
  end
  return out
end

--- Checks options against rules { name = { "positive" | "non_negative" | "count", unit } };
--- the error names the option and its unit. Whole-number options become integers.
function agglomerate.check(o, rules, context)
  for name, rule in pairs(rules) do
    local v, kind, unit = o[name], rule[1], rule[2] or "-"
    local ok
    if kind == "count" then
      local n = type(v) == "number" and math.tointeger(v) or nil
      ok = n ~= nil and n >= 1
      if ok then o[name] = n end
    elseif type(v) ~= "number" or v ~= v or v == math.huge then
      ok = false
    elseif kind == "positive" then
      ok = v > 0
    else
      ok = v >= 0
    end
    if not ok then
      local wanted = kind == "count" and "a whole number >= 1" or (kind == "positive" and "> 0" or ">= 0")
      raise(string.format("%s: '%s' must be %s [%s], got %s", context, name, wanted, unit, tostring(v)))
    end
  end
end

local function zero_vector(dimension)
  if dimension == 3 then return { 0, 0, 0 } end
  return { 0, 0 }
end

-- e_k: the unit vector along axis k (1 = x, 2 = y, 3 = z) scaled by s.
local function axis_vector(dimension, k, s)
  local v = zero_vector(dimension)
  v[k] = s
  return v
end
agglomerate.axis_vector = axis_vector

-- ---------------------------------------------------------------------------
-- Size distribution (Fig. 7.9) and random placement (Fig. 7.10)
-- ---------------------------------------------------------------------------

--- The diameters of `classes` size classes spread evenly over
--- mean (1 - spread) .. mean (1 + spread): seven classes over 5 um +- 5 % by default.
function agglomerate.size_classes(mean_diameter, spread, classes)
  local o = { mean_diameter = mean_diameter, size_spread = spread, size_classes = classes }
  agglomerate.check(o, { mean_diameter = { "positive", "m" }, size_spread = { "non_negative" },
                         size_classes = { "count" } }, "size_classes")
  if spread >= 1 then raise("size_classes: 'size_spread' must be < 1 (a fraction of the mean)") end
  local out = {}
  for k = 0, o.size_classes - 1 do
    local fraction = o.size_classes == 1 and 0 or (2 * k / (o.size_classes - 1) - 1)
    out[#out + 1] = mean_diameter * (1 + spread * fraction)
  end
  return out
end

--- `count` diameters, equal numbers in each class (Fig. 7.9 is lost; 217 =
--- 7 x 31 suggests equal counts), in an order shuffled by math.random.
function agglomerate.primary_diameters(count, classes)
  local out = {}
  for k = 1, count do out[k] = classes[(k - 1) % #classes + 1] end
  for k = count, 2, -1 do  -- Fisher-Yates
    local j = math.random(k)
    out[k], out[j] = out[j], out[k]
  end
  return out
end

-- A uniform random point in the ball of radius r about the origin.
local function random_in_ball(dimension, r)
  while true do
    local x, s = {}, 0
    for k = 1, dimension do
      x[k] = (2 * math.random() - 1) * r
      s = s + x[k] * x[k]
    end
    if s <= r * r then return x end
  end
end

-- The neighbour cells of a cell (itself included), as offsets.
local function cell_offsets(dimension)
  local out = {}
  for a = -1, 1 do
    for b = -1, 1 do
      if dimension == 2 then
        out[#out + 1] = { a, b }
      else
        for c = -1, 1 do out[#out + 1] = { a, b, c } end
      end
    end
  end
  return out
end

--- Random positions for spheres of the given radii inside a circle (2D) or
--- sphere (3D) of `region_radius` about `center`, without overlaps. Centres are
--- drawn uniformly; overlaps are then removed by moving each overlapping pair
--- apart along its line of centres (a geometric relaxation, no dynamics),
--- because 217 discs covering 54 % of a 100 um circle are beyond what random
--- sequential addition can place (its jamming limit is 0.547 in an unbounded
--- plane, lower against a boundary). `clearance` is the gap left between
--- neighbours, a fraction of the sum of their radii. Returns the positions and
--- the number of sweeps, or raises an error when the region cannot hold them.
--- Refuses n primaries of total area (2D) or volume (3D) `solid` that would
--- fill more of the generation region than can be placed at random.
function agglomerate.check_fill(dimension, region_radius, n, solid, context)
  local region = dimension == 2 and math.pi * region_radius ^ 2 or 4 / 3 * math.pi * region_radius ^ 3
  local limit = dimension == 2 and 0.75 or 0.55  -- well below random close packing (0.82, 0.64)
  if solid / region > limit then
    raise(string.format("%s: generation_diameter %.4g m is too small for %d primaries: they would fill %.0f %% of "
      .. "it (at most %.0f %% can be placed at random)", context, 2 * region_radius, n, 100 * solid / region, 100 * limit))
  end
end

function agglomerate.random_positions(dimension, center, region_radius, radii, clearance, max_sweeps)
  local n = #radii
  local r_max, solid = 0, 0
  for i = 1, n do
    r_max = math.max(r_max, radii[i])
    solid = solid + (dimension == 2 and math.pi * radii[i] ^ 2 or 4 / 3 * math.pi * radii[i] ^ 3)
  end
  agglomerate.check_fill(dimension, region_radius, n, solid, "random_positions")
  local positions = {}
  for i = 1, n do positions[i] = random_in_ball(dimension, region_radius - radii[i]) end
  local cell = 2 * r_max * (1 + clearance)
  local offsets = cell_offsets(dimension)
  local function cell_name(x, offset)
    local parts = {}
    for k = 1, dimension do parts[k] = math.floor(x[k] / cell) + (offset and offset[k] or 0) end
    return table.concat(parts, ",")
  end
  local function build_grid()
    local grid = {}
    for i = 1, n do
      local name = cell_name(positions[i])
      grid[name] = grid[name] or {}
      table.insert(grid[name], i)
    end
    return grid
  end
  -- Whether any two primaries overlap where they stand now (a sweep's pushes and
  -- its clamp back into the region move pairs it has already passed).
  local function any_overlap()
    local grid = build_grid()
    for i = 1, n do
      local xi = positions[i]
      for _, offset in ipairs(offsets) do
        for _, j in ipairs(grid[cell_name(xi, offset)] or {}) do
          if j > i then
            local dist2 = 0
            for k = 1, dimension do dist2 = dist2 + (positions[j][k] - xi[k]) ^ 2 end
            if dist2 < (radii[i] + radii[j]) ^ 2 then return true end
          end
        end
      end
    end
    return false
  end
  for sweep = 1, max_sweeps do
    local grid = build_grid()
    local overlapping = false
    for i = 1, n do
      local xi = positions[i]
      for _, offset in ipairs(offsets) do
        for _, j in ipairs(grid[cell_name(xi, offset)] or {}) do
          if j > i then
            local xj = positions[j]
            local dx, dist2 = {}, 0
            for k = 1, dimension do
              dx[k] = xj[k] - xi[k]
              dist2 = dist2 + dx[k] * dx[k]
            end
            local dist = math.sqrt(dist2)
            local wanted = (radii[i] + radii[j]) * (1 + clearance)
            if dist < wanted then
              if dist < radii[i] + radii[j] then overlapping = true end
              if dist == 0 then dx, dist = axis_vector(dimension, 1, 1), 1 end
              local push = 0.5 * (wanted - dist) / dist
              for k = 1, dimension do
                xi[k] = xi[k] - push * dx[k]
                xj[k] = xj[k] + push * dx[k]
              end
            end
          end
        end
      end
    end
    for i = 1, n do  -- back inside the region
      local x, r2 = positions[i], 0
      for k = 1, dimension do r2 = r2 + x[k] * x[k] end
      local reach = region_radius - radii[i]
      if r2 > reach * reach then
        for k = 1, dimension do x[k] = x[k] * reach / math.sqrt(r2) end
      end
    end
    if not overlapping and not any_overlap() then
      for i = 1, n do
        for k = 1, dimension do positions[i][k] = positions[i][k] + center[k] end
      end
      return positions, sweep
    end
  end
  raise(string.format("random_positions: overlaps remain after %d sweeps; enlarge generation_diameter (%.4g m) "
    .. "or lower count (%d)", max_sweeps, 2 * region_radius, n))
end

agglomerate.zero_vector = zero_vector

return agglomerate
