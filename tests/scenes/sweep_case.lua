-- One case of the `granule sweep` tests (tests/app/sweep_test.py): a sphere in
-- free flight, so every result is a closed-form function of the parameters
-- the sweep sets, and a case can be told to fail (a Lua error, the process
-- killed by a signal, a time step the engine refuses) so that the tests can
-- check the others carry on.
local p = parameters {
  speed = { default = 1.0, unit = "m/s", doc = "velocity of the sphere along x" },
  duration = { default = 0.01, unit = "s", doc = "time of flight" },
  radius = { default = 1e-3, unit = "m" },
  density = { default = 2500, unit = "kg/m^3" },
  fail_speed = { default = -1, unit = "m/s", doc = "this speed ends with a Lua error" },
  crash_speed = { default = -1, unit = "m/s", doc = "this speed kills its own process (SIGSEGV)" },
  unstable_speed = { default = -1, unit = "m/s", doc = "this speed asks for a time step the engine refuses" },
  hold = { default = 0, unit = "s", doc = "wall time to sleep, so that parallel cases overlap" },
  busy = { default = 0, unit = "s", doc = "wall time to keep Lua busy (Ctrl-C stops it at once)" },
}
local sim = simulation { dimension = 2, time_step = p.speed == p.unstable_speed and 1 or 1e-5 }
sim:material { name = "glass", density = p.density }
sim:contact { "glass", "glass", model = "linear", k_normal = 1e2, restitution = 0.9, friction = 0.3 }
local ball = sim:add_particle { position = { 0, 0 }, velocity = { p.speed, 0 }, radius = p.radius,
                                material = "glass" }
sim:output {}
if p.speed == p.fail_speed then
  -- A line of the scene's own that looks like an error: the summary must report the error
  -- the case ended on, not this.
  print("error: 1e-3 off the closed form (a line the scene printed)")
  error(string.format("speed %g is the one told to fail", p.speed))
end
if p.speed == p.crash_speed then
  os.execute("kill -SEGV $PPID")  -- the shell's parent is this granule process
  while true do end
end
sim:run { duration = p.duration }
-- os.execute ignores SIGINT while it waits (system(3)), so `hold` is for the MPI test and
-- `busy` for the Ctrl-C test.
if p.hold > 0 then os.execute(string.format("sleep %g", p.hold)) end
local until_time = wall_time() + p.busy
while wall_time() < until_time do end
local b = sim:particle(ball)
-- Free flight: x = v t (the leap-frog is exact without forces); m = pi d^3 rho / 6 (SPEC 2).
sim:result { distance = b.position[1], mass = b.mass, momentum = b.mass * b.velocity[1],
             flight_time = sim:time() }
-- Named as a parameter and as the summary's own status column: the summaries
-- keep both, these as result_speed and result_status.
sim:result { speed = b.velocity[1], status = 1 }
print(string.format("sweep_case speed=%g distance=%.6g", p.speed, b.position[1]))
