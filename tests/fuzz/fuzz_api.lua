-- Feeds every documented API function malformed arguments and checks that each
-- bad call is refused with a message (a Lua error caught by pcall), never a
-- crash. The functions, their arguments and a valid example call come from the
-- documentation table (api_reference()), so a new function is fuzzed as soon as
-- it is documented, and a documented key that the binding does not accept is
-- reported too.
--
--   build/granule run tests/fuzz/fuzz_api.lua --quiet      (ctest: fuzz.api)
local granule = require "granule"

local failures, calls = {}, 0
local function fail(fmt, ...) failures[#failures + 1] = string.format(fmt, ...) end

local fixture_file = "fuzz_fixture.h5"
-- The file sim:load_particles's documented example reads.
do
  local saved = simulation { dimension = 2 }
  saved:material { name = "glass", density = 2500 }
  saved:add_particle { position = { 0, 0 }, radius = 5e-4, material = "glass" }
  saved:output { file = "agglomerate.h5", xdmf = false }
  saved:snapshot()
  saved:close()
end
-- Only these need the fixture's output file (creating one per call costs time).
local needs_output = { ["sim:snapshot"] = true, ["sim:series"] = true, ["sim:append"] = true,
                       ["sim:result"] = true, ["sim:close"] = true, ["sim:plot"] = true }
local function fixture(with_output)
  local sim = simulation { dimension = 2, record_contacts = true }
  sim:material { name = "glass", density = 2500 }
  sim:material { name = "steel", density = 7800 }
  sim:contact { "glass", "glass", model = "walton_braun", k_load = 1e4, restitution = 0.9, friction = 0.3 }
  sim:contact { "glass", "steel", model = "walton_braun", k_load = 1e4, restitution = 0.9, friction = 0.5 }
  sim:wall_cylinder { name = "drum", center = { 0, 0 }, radius = 0.01, material = "steel" }
  sim:wall_plane { name = "floor", point = { 0, -0.009 }, normal = { 0, 1 }, material = "steel" }
  sim:fill { region = { circle = { center = { 0, 0 }, radius = 0.008 } }, count = 20, radius = 5e-4,
             material = "glass", seed = 1 }
  sim:central_field { point = { 0, 0 }, strength = 0 }  -- for sim:set_central_strength's example
  if with_output then
    sim:output { file = fixture_file }
    sim:series("probe", { "time", "value" })
  end
  return sim
end

-- Values that no argument of any type accepts unchanged, by what they try.
local nan, inf = 0 / 0, math.huge
local bad_numbers = { nan, inf, -inf }
local huge_numbers = { 1e308, -1e308, math.maxinteger, math.mininteger, 1e-320 }
local wrong_type = {
  number = { "1", {}, true, print }, integer = { "1", {}, true, 1.5, print },
  string = { 1, {}, true, print }, boolean = { 1, "true", {}, print },
  vector = { 1, "x", {}, { 1 }, { 1, 2, 3, 4 }, { "a", 1 }, { nan, 0 }, { inf, 0 } },
  table = { 1, "x", true, print }, list = { 1, "x", true, print },
  ["function"] = { 1, "x", {}, true },
}

local function describe(v)
  if type(v) == "table" then
    local parts = {}
    for i = 1, #v do parts[i] = tostring(v[i]) end
    return "{" .. table.concat(parts, ", ") .. "}"
  end
  return type(v) == "string" and string.format("%q", v) or tostring(v)
end

local function target(doc, sim)
  local name = doc.name
  if name:sub(1, 4) == "sim:" then
    local method = name:sub(5)
    return function(...) return sim[method](sim, ...) end
  elseif name:sub(1, 8) == "granule." then
    local f = granule
    for part in name:sub(9):gmatch("[^.]+") do f = f[part] end
    return f
  end
  return _ENV[name]
end

local function example_args(doc, sim)
  if doc.example == "" then return {}, 0 end
  local env = setmetatable({ sim = sim }, { __index = _ENV })
  local chunk = assert(load("return " .. doc.example, "=example of " .. doc.name, "t", env))
  local args = table.pack(chunk())
  return args, args.n
end

-- Calls f with args under pcall; returns ok and the message (checked to be a string).
local function attempt(doc, what, f, args, n)
  calls = calls + 1
  local result = table.pack(pcall(f, table.unpack(args, 1, n)))
  if not result[1] and (type(result[2]) ~= "string" or result[2] == "") then
    fail("%s %s: error object is %s, not a message", doc.name, what, type(result[2]))
  end
  return result[1], result[2]
end

local function copy(t)
  local c = {}
  for k, v in pairs(t) do c[k] = v end
  return c
end

-- After a call that a huge value got through, the simulation must still fail
-- cleanly or run; it must not crash.
local function still_sane(doc, what, sim)
  local ok, message = pcall(sim.run, sim, { steps = 2 })
  if not ok and type(message) ~= "string" then fail("%s %s: run afterwards raised a non-message", doc.name, what) end
  pcall(sim.stats, sim)
end

local skipped = { parameters = "once per scene: tests/fuzz/fuzz_cli.sh feeds it malformed declarations",
                  ["sim:wall_mesh"] = "3D only, the fixture is 2D: tests/scenes/mesh_api_check.lua checks it" }

for _, doc in ipairs(api_reference()) do
  if doc.form == "value" or skipped[doc.name] then goto continue end
  local function fresh()
    local sim = fixture(needs_output[doc.name])
    local args, n = example_args(doc, sim)
    -- A run must end even when a huge step count gets through.
    if doc.name == "sim:run" then args[1].stop_when = function() return true end end
    return sim, target(doc, sim), args, n
  end
  local function done(sim) pcall(sim.close, sim) end

  -- The example itself must work (the docs cannot rot).
  do
    local sim, f, args, n = fresh()
    local ok, message = attempt(doc, "example", f, args, n)
    if not ok then fail("%s: the documented example fails: %s", doc.name, message) end
    done(sim)
  end

  -- Wrong arity: one argument too many, and none at all when some are required.
  do
    local sim, f, args, n = fresh()
    local most = doc.form == "table" and 1 or #doc.args
    args[most + 1] = 1
    if attempt(doc, "with an extra argument", f, args, most + 1) then
      fail("%s accepted an extra argument", doc.name)
    end
    done(sim)
  end
  local requires = doc.form == "table" and not doc.table_optional
  for _, a in ipairs(doc.args) do requires = requires or (doc.form == "positional" and a.required) end
  if requires then
    local sim, f = fresh()
    if attempt(doc, "without arguments", f, {}, 0) then fail("%s accepted no arguments", doc.name) end
    done(sim)
  end

  -- One argument at a time: missing, wrong type, not finite, huge.
  for index, a in ipairs(doc.args) do
    local key = doc.form == "table" and (tonumber(a.name) or a.name) or index
    if type(key) == "string" and key:sub(1, 1) == "<" then goto next_arg end
    local function perturbed(value)
      local sim, f, args, n = fresh()
      if doc.form == "table" then
        args[1] = copy(args[1] or {})
        args[1][key] = value
      else
        args[key] = value
        n = math.max(n, key)
      end
      return sim, f, args, n
    end
    local function must_refuse(value, what)
      local sim, f, args, n = perturbed(value)
      local ok, message = attempt(doc, what, f, args, n)
      if ok then
        fail("%s accepted %s = %s (%s)", doc.name, a.name, describe(value), what)
      elseif type(key) == "string" and message:find("unknown key '" .. key .. "'", 1, true) then
        fail("%s: documented key '%s' is refused as unknown", doc.name, key)
      end
      done(sim)
    end
    if a.required then must_refuse(nil, "missing") end
    for _, v in ipairs(wrong_type[a.type] or {}) do must_refuse(v, "wrong type") end
    if a.type == "number" or a.type == "integer" then
      for _, v in ipairs(bad_numbers) do must_refuse(v, "not finite") end
      for _, v in ipairs(huge_numbers) do
        local sim, f, args, n = perturbed(v)
        local what = "huge " .. a.name .. " = " .. describe(v)
        if attempt(doc, what, f, args, n) then still_sane(doc, what, sim) end
        done(sim)
      end
    end
    if a.type == "vector" then
      for _, v in ipairs({ { 1e308, 0 }, { -1e308, 1e308 } }) do
        local sim, f, args, n = perturbed(v)
        local what = "huge " .. a.name .. " = " .. describe(v)
        if attempt(doc, what, f, args, n) then still_sane(doc, what, sim) end
        done(sim)
      end
    end
    ::next_arg::
  end

  -- Unknown keys in a table argument.
  if doc.form == "table" and not doc.open_keys then
    local sim, f, args, n = fresh()
    args[1] = copy(args[1] or {})
    args[1].no_such_key = 1
    local ok, message = attempt(doc, "with an unknown key", f, args, math.max(n, 1))
    if ok then
      fail("%s accepted an unknown key", doc.name)
    elseif not message:find("no_such_key", 1, true) then
      fail("%s: the message for an unknown key does not name it: %s", doc.name, message)
    end
    done(sim)
  end
  ::continue::
end

os.remove(fixture_file)
os.remove("example_output.h5")
os.remove("example_output.xmf")
os.remove("example_picture.svg")
os.remove("fuzz_fixture.xmf")
if #failures > 0 then
  for _, f in ipairs(failures) do io.stderr:write("FAIL ", f, "\n") end
  error(string.format("%d of %d malformed calls were not refused properly", #failures, calls))
end
print(string.format("fuzz_api ok: %d calls over %d documented functions", calls, #api_reference()))
