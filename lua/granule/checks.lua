-- granule.checks: argument validation shared by the analysis modules
-- (granule.materials, granule.coating, granule.kinetic).
--
-- Every check raises a Lua error that names the function and the parameter,
-- so a bad value in a scene, the REPL or a tool points at what to fix. The
-- error's position is the first caller outside this library folder, i.e. the
-- line of the scene or test that passed the value.
local M = {}

local names = require "granule.names"

-- "@/path/to/lua/granule/" : frames from this folder are library frames.
local library_prefix = debug.getinfo(1, "S").source:match("^(@.*[/\\])[^/\\]*$")

local function raise(message)
  -- debug.getinfo(k) and error(message, k) count levels the same way:
  -- 1 is this function, 2 its caller, ... (no tail calls here, they drop frames).
  local level = 2
  while true do
    local info = debug.getinfo(level, "S")
    if not info then
      error(message, 0)
    end
    local from_library = library_prefix and info.source:sub(1, #library_prefix) == library_prefix
    if not from_library and info.what ~= "C" then
      error(message, level)
    end
    level = level + 1
  end
end
M.raise = raise

local function describe(value)
  if type(value) == "number" then
    if value ~= value then return "nan" end
    return string.format("%.6g", value)
  end
  if type(value) == "string" then return string.format("%q", value) end
  return tostring(value)
end

--- M.fail(where, name, requirement, value): raise "where: 'name' must be
--- requirement (got value)" at the first caller outside the library.
function M.fail(where, name, requirement, value)
  raise(string.format("%s: '%s' must be %s (got %s)", where, name, requirement, describe(value)))
end

--- M.number(where, name, value, unit): a finite number, or an error.
function M.number(where, name, value, unit)
  if type(value) ~= "number" or value ~= value or value == math.huge or value == -math.huge then
    M.fail(where, name, "a finite number" .. (unit and (" in " .. unit) or ""), value)
  end
  return value
end

--- M.positive(where, name, value, unit): a finite number > 0.
function M.positive(where, name, value, unit)
  M.number(where, name, value, unit)
  if value <= 0 then M.fail(where, name, "> 0" .. (unit and (" " .. unit) or ""), value) end
  return value
end

--- M.non_negative(where, name, value, unit): a finite number >= 0.
function M.non_negative(where, name, value, unit)
  M.number(where, name, value, unit)
  if value < 0 then M.fail(where, name, ">= 0" .. (unit and (" " .. unit) or ""), value) end
  return value
end

--- M.open_interval(where, name, value, low, high): low < value < high.
function M.open_interval(where, name, value, low, high)
  M.number(where, name, value)
  if not (value > low and value < high) then
    M.fail(where, name, string.format("in (%g, %g)", low, high), value)
  end
  return value
end

--- M.half_open(where, name, value, low, high): low < value <= high.
function M.half_open(where, name, value, low, high)
  M.number(where, name, value)
  if not (value > low and value <= high) then
    M.fail(where, name, string.format("in (%g, %g]", low, high), value)
  end
  return value
end

--- M.table_arg(where, value, what): the keyword table a public function takes.
function M.table_arg(where, value, what)
  if type(value) ~= "table" then
    raise(string.format("%s: expected a table { %s }, got %s", where, what, type(value)))
  end
  return value
end

--- M.nearest(name, candidates): the candidate closest to name, or nil when
--- none is close enough: core/names.cpp's nearest_name, the one the C++
--- errors use (case-insensitive edit distance at most max(3, #name / 3)).
function M.nearest(name, candidates)
  return names.nearest_name(name, candidates)
end

--- M.known_keys(where, t, allowed): refuse keys of t that are not in the
--- list allowed, suggesting the nearest one (scenes are strict, STYLE 10).
function M.known_keys(where, t, allowed)
  local set = {}
  for _, k in ipairs(allowed) do set[k] = true end
  for k in pairs(t) do
    if not set[k] then
      local hint = type(k) == "string" and M.nearest(k, allowed)
      raise(string.format("%s: unknown key '%s'%s", where, tostring(k),
        hint and string.format(" (did you mean '%s'?)", hint) or ""))
    end
  end
  return t
end

return M
