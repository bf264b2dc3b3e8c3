-- simulation called with a number instead of a table
-- expect: sim_not_a_table\.lua:3\b.*simulation
local sim = simulation(2)  -- <- wrong
