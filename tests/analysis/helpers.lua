-- Assertions shared by the analysis tests (loaded with dofile next to them).
local H = {}

--- H.near(actual, expected, tolerance, what): |actual - expected| <= tolerance.
function H.near(actual, expected, tolerance, what)
  if type(actual) ~= "number" or actual ~= actual or math.abs(actual - expected) > tolerance then
    error(string.format("%s: got %.10g, expected %.10g +- %.3g", what, tonumber(actual) or 0 / 0, expected,
      tolerance), 2)
  end
end

--- H.relative(actual, expected, relative_tolerance, what): |actual/expected - 1| <= tolerance.
function H.relative(actual, expected, relative_tolerance, what)
  if type(actual) ~= "number" or actual ~= actual
     or math.abs(actual - expected) > relative_tolerance * math.abs(expected) then
    error(string.format("%s: got %.10g, expected %.10g (relative tolerance %.1g)", what, tonumber(actual) or 0 / 0,
      expected, relative_tolerance), 2)
  end
end

--- H.fails(pattern, f, ...): f(...) raises an error whose message contains `pattern` (plain text).
function H.fails(pattern, f, ...)
  local ok, message = pcall(f, ...)
  if ok then error(string.format("expected an error mentioning %q, but the call succeeded", pattern), 2) end
  if not tostring(message):find(pattern, 1, true) then
    error(string.format("expected an error mentioning %q, got: %s", pattern, tostring(message)), 2)
  end
  return message
end

--- H.check(condition, message): assert with a message (a readable alias).
function H.check(condition, message)
  if not condition then error(message, 2) end
end

return H
