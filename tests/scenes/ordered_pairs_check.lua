-- pairs() in an order fixed by the keys (src/lua/ordered_pairs.hpp), with Lua's own
-- semantics otherwise: every key once, fields set to nil during the loop skipped,
-- __pairs obeyed, one argument.
local function keys_of(t)
  local out = {}
  for k, v in pairs(t) do
    assert(t[k] == v, "pairs gave a value that is not the key's")
    out[#out + 1] = tostring(k)
  end
  return table.concat(out, " ")
end
-- Numbers by value, then false, true, then strings by their bytes.
assert(keys_of { b = 1, a = 2, [3] = 3, [1.5] = 4, [-2] = 5, [true] = 6, [false] = 7, B = 8 } ==
       "-2 1.5 3 false true B a b", keys_of { b = 1, a = 2, [3] = 3, [1.5] = 4, [-2] = 5, [true] = 6, [false] = 7, B = 8 })
-- A sequence in index order, a sequence with a hole by value.
local seq = {}
for i = 1, 1000 do seq[i] = i * i end
local n, last = 0, 0
for i, v in pairs(seq) do
  n = n + 1
  assert(i == last + 1 and v == i * i, "sequence out of order at " .. i)
  last = i
end
assert(n == 1000, "sequence: " .. n .. " keys")
assert(keys_of { 10, nil, 30, x = 1 } == "1 3 x", keys_of { 10, nil, 30, x = 1 })
-- Fields set to nil during the loop (the visited one, and one ahead) as next allows.
local t = { 1, 2, 3, 4, 5, a = 1, b = 2, c = 3 }
local seen = {}
for k in pairs(t) do
  seen[#seen + 1] = tostring(k)
  t[k] = nil
  if k == 2 then t[4] = nil end
  if k == "a" then t.c = nil end
end
assert(table.concat(seen, " ") == "1 2 3 5 a b", table.concat(seen, " "))
local s = { 1, 2, 3 }
seen = {}
for k in pairs(s) do seen[#seen + 1] = k; if k == 1 then s[2] = nil end end
assert(table.concat(seen, " ") == "1 3", table.concat(seen, " "))
-- Keys of other types: every one once, after the others.
local ka, kb = {}, function() end
local mixed = { [ka] = 1, [kb] = 2, z = 3, [1] = 4 }
local count, before_others = 0, true
for k in pairs(mixed) do
  count = count + 1
  if type(k) == "table" or type(k) == "function" then before_others = false
  else assert(before_others, "a key of another type before a string or number") end
end
assert(count == 4, "mixed: " .. count .. " keys")
-- __pairs is obeyed; one argument only; the empty table gives nothing.
local proxy = setmetatable({}, { __pairs = function() return function(_, k) if not k then return 1, "one" end end, nil, nil end })
local got = {}
for k, v in pairs(proxy) do got[#got + 1] = k .. "=" .. v end
assert(table.concat(got, " ") == "1=one", table.concat(got, " "))
assert(not pcall(pairs, {}, 1), "pairs took two arguments")
for _ in pairs {} do error("the empty table gave a key") end
print("ordered pairs check ok")
