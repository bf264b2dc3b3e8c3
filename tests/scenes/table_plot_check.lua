-- sim:table and sim:plot (src/lua/wrap_table_plot.cpp): the table's numbers are the
-- particles' (as sim:particle gives them, to its 6 digits), the plot is a PNG named after
-- the output and the column, and misspelt names are refused with the nearest one.
local sim = simulation { dimension = 2, time_step = 1e-6 }
sim:material { name = "glass", density = 2500 }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e3, restitution = 0.9, friction = 0.3 }
for k = 0, 2 do
  -- Values of many digits, so that a table of fewer than 6 would differ.
  sim:add_particle { position = { k * 2.71828e-3, 0.00314159 }, velocity = { 0.1234567 * (1 - k), 0.0234567 * k },
                     radius = 1.23457e-3, material = "glass" }
end
sim:gravity { 0, -9.81 }
sim:output { file = "table_plot_test.h5" }
sim:run { steps = 2000 }
local text = sim:table { ids = { 0, 2 }, fields = { "id", "x", "vy", "mass" } }
local lines = {}
for line in text:gmatch("[^\n]+") do lines[#lines + 1] = line end
assert(#lines == 3, "a heading and two rows, got " .. #lines)
assert(lines[1]:match("^%s+id%s+x%s+vy%s+mass$"), lines[1])
for row, id in ipairs { 0, 2 } do
  local b, cells = sim:particle(id), {}
  for cell in lines[row + 1]:gmatch("%S+") do cells[#cells + 1] = cell end
  assert(cells[1] == tostring(id), "id " .. cells[1])
  -- 6 significant digits: within half a unit of the sixth.
  for k, v in ipairs { b.position[1], b.velocity[2], b.mass } do
    local shown = tonumber(cells[k + 1])
    assert(math.abs(shown - v) <= 5e-6 * math.abs(v) + 1e-300 and math.abs(shown - v) <= 0.51 * 10 ^ (math.floor(math.log(math.abs(v), 10)) - 5),
           string.format("row %d cell %d: %s, the value is %.17g", row, k + 1, cells[k + 1], v))
  end
end
local ok, err = pcall(sim.table, sim, { fields = { "vel" } })
assert(not ok and err:find("no field 'vel'"), err)
local png = sim:plot("kinetic_energy")
assert(png == "table_plot_test_kinetic_energy.png", png)
local f = assert(io.open(png, "rb"))
assert(f:read(8) == "\137PNG\r\n\26\n", "not a PNG")
f:close()
ok, err = pcall(sim.plot, sim, "kinetc_energy_translational")
assert(not ok and err:find("did you mean 'kinetic_energy_translational'"), err)
print("table_plot ok: " .. png)
