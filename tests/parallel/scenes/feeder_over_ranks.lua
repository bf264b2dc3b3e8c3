-- A feeder over ranks: the scene starts with no particles and a callback adds
-- one every 50 steps onto a floor; its run's stop criterion may answer
-- differently on one rank (mode = "stop_on_rank1") or fail there
-- ("error_on_rank1"). Prints every particle's final state in hex, writes a
-- file through io.output and a table through sim:table.
local p = parameters {
  mode = { default = "feed", doc = "feed | stop_on_rank1 | error_on_rank1 | long (a run to be signalled)" },
  canonical = { default = 0, min = 0, max = 1, integer = true, doc = "1: canonical order (as ranks)" },
}
local rank = tonumber(os.getenv("OMPI_COMM_WORLD_RANK") or "0")
local sim = simulation { dimension = 2, time_step = 2e-6 }
sim:set { canonical_order = p.canonical == 1 }
sim:material { name = "grain", density = 2500 }
sim:material { name = "steel", density = 7800 }
sim:contact { "grain", "grain", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:contact { "grain", "steel", model = "linear", k_normal = 1e3, restitution = 0.5, friction = 0.3 }
sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel" }
sim:gravity { 0, -9.81 }
local fed = 0
sim:every { steps = 50, function(s)
  fed = fed + 1
  s:add_particle { position = { (fed % 7) * 0.6e-3, 3e-3 }, radius = 0.25e-3, material = "grain",
                   velocity = { 0, -0.5 } }
end }
if p.mode == "long" then  -- each rank names its process, for a test to signal one
  local stat = io.open("/proc/self/stat")
  io.stderr:write(string.format("pid of rank %d: %d\n", rank, stat:read("n")))
  stat:close()
end
sim:run { steps = p.mode == "long" and 100000000 or 1500, check_every = 100, stop_when = function(s)
  if rank == 1 and s:step_count() >= 500 then
    if p.mode == "stop_on_rank1" then return true end
    if p.mode == "error_on_rank1" then error("the criterion failed on rank 1") end
  end
  return false
end }
for _, id in ipairs(sim:particles()) do
  local q = sim:particle(id)
  print(string.format("state %d %a %a %a %a %a", id, q.position[1], q.position[2], q.velocity[1],
    q.velocity[2], q.spin))
end
-- What a scene writes besides print: rank 0 alone writes it where named.
local f = io.output("io_output.txt")
io.write("written by rank ", rank, "\n")
io.close(f)
io.output(io.stdout)
io.write("io.write to the terminal\n")
sim:table { ids = { 0, 1 }, fields = { "id", "x" } }
print("done", sim:step_count())
