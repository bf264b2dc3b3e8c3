-- runtime error: a misspelled global function
-- expect: lua_misspelled_global\.lua:3\b.*undeclared global 'simulaton' \(did you mean 'simulation'\?\)
local sim = simulaton { dimension = 2 }  -- <- wrong
