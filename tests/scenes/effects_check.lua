-- The run header says what a scene simulates: adhesion only for adhesive
-- pairs that can meet, rotation only with friction, moving walls, fields; an
-- adhesive law declared for a material no particle has neither runs nor widens
-- the skin. tests/scenes/effects_check.py then reads /scene/effects.
local p = parameters { out = { default = "effects_check.h5" } }
local function scene(opts)
  local sim = simulation { dimension = 2 }
  sim:material { name = "powder", density = 1200, young = 1e8, poisson = 0.3 }
  -- very soft and sticky: its JKR contacts last until the surfaces are ~0.5 mm apart (Eq. 6.14),
  -- more than the automatic skin of 0.1 mm
  sim:material { name = "glue", density = 1200, young = 1e4, poisson = 0.3, surface_energy = 2 }
  sim:material { name = "steel", density = 0, young = 2e11, poisson = 0.3 }
  sim:contact { "powder", "powder", model = "linear", k_normal = 2e4, restitution = 0.9, friction = opts.friction }
  sim:contact { "powder", "steel", model = "linear", k_normal = 2e4, restitution = 0.9, friction = opts.friction }
  if opts.glue_law then
    sim:contact { "glue", "glue", model = "thornton_jkr", friction = 0.3 }
    sim:contact { "glue", "powder", model = "thornton_jkr", friction = 0.3 }
    sim:contact { "glue", "steel", model = "thornton_jkr", friction = 0.3 }
  end
  sim:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "steel",
                   velocity = opts.moving and { 0.01, 0 } or nil }
  sim:add_particle { position = { 0, 1e-3 }, radius = 0.2e-3, material = "powder", spin = 5 }
  sim:add_particle { position = { 1e-3, 1e-3 }, radius = 0.2e-3, material = opts.glue_particle and "glue" or "powder" }
  if opts.gravity then sim:gravity(opts.gravity) end
  sim:run { steps = 10 }
  return sim, sim:describe()
end
local function has(text, piece, what)
  assert(text:find(piece, 1, true), string.format("%s: the header lacks '%s':\n%s", what, piece, text))
end
local function skin_of(text) return tonumber(text:match("skin ([%d%.e%-]+) m")) end

-- Before its first run an automatic time step is not chosen yet: the header says so, not "0 s".
do
  local early = simulation { dimension = 3 }
  early:material { name = "m", density = 1200, young = 1e8, poisson = 0.3 }
  early:contact { "m", "m", model = "hertz_mindlin", restitution = 0.5, friction = 0.3 }
  early:add_particle { position = { 0, 0, 0 }, radius = 1e-3, material = "m" }
  local before = early:describe()
  has(before, "time step: not chosen yet", "before the first run")
  assert(not before:find("time step: 0 s", 1, true), "before the first run: 'time step: 0 s'\n" .. before)
  early:run { steps = 1 }
  assert(skin_of(early:describe()) > 0, "after a run the header gives the skin")
  early:close()
end

local _, plain = scene { friction = 0.4 }
has(plain, "adhesion: off", "plain")
has(plain, "rotation: spins integrated", "plain")
has(plain, "moving walls: none", "plain")
has(plain, "gravity: off", "plain")

local frictionless, text = scene { friction = 0 }
has(text, "rotation: off", "friction 0")
-- No torque acts, and the spin the scene gave stays as it was.
local spin = frictionless:particle(0).spin
assert(spin == 5, "a frictionless particle's spin changed to " .. spin)

-- Friction switched on by a hook in the middle of a run (no prepare() in between):
-- the spins must follow from that step on, not from the next run.
do
  local sim = simulation { dimension = 2 }
  sim:material { name = "m", density = 1200 }
  sim:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0 }
  local a = sim:add_particle { position = { 0, 0 }, velocity = { 0, 0.5 }, radius = 0.2e-3, material = "m" }
  sim:add_particle { position = { 0.39e-3, 0 }, velocity = { 0, -0.5 }, radius = 0.2e-3, material = "m" }
  local switched = false
  sim:every { steps = 1, function(s)
    if not switched then s:set_contact("m", "m", { friction = 0.5 }) switched = true end
  end }
  sim:run { steps = 10 }  -- one chunk of sim:run: no prepare() before its end
  assert(sim:particle(a).spin ~= 0, "friction switched on mid-run, but the spins were not integrated")
end

local _, declared = scene { friction = 0.4, glue_law = true }
has(declared, "adhesion: off", "JKR declared, no glue particle")
assert(skin_of(declared) == skin_of(plain),
  string.format("an unused adhesive law changed the skin from %s to %s m", skin_of(plain), skin_of(declared)))

local _, glued = scene { friction = 0.4, glue_law = true, glue_particle = true }
has(glued, "adhesion: on (", "a glue particle")
has(glued, "glue-glue thornton_jkr", "a glue particle")
assert(skin_of(glued) > skin_of(plain), "the JKR reach did not widen the skin")

local sim, moving = scene { friction = 0.4, moving = true, gravity = { 0, 0 } }
has(moving, "moving walls: floor", "moving floor")
has(moving, "gravity: off", "gravity declared zero")
sim:output { file = p.out }
sim:run { steps = 1 }
sim:snapshot()  -- the header (and /walls) is in the file now
-- a wall added after the header must still reach /walls (effects_check.py checks)
sim:wall_plane { name = "lid", point = { 0, 5e-3 }, normal = { 0, -1 }, material = "steel" }
sim:run { steps = 1 }
sim:close()

-- A pair's rolling model reads back by name wherever a person or a reader sees it:
-- sim:contact_parameters, describe() and /contacts/<pair> in the output.
do
  local r = simulation { dimension = 2 }
  r:material { name = "m", density = 1200 }
  r:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0.3,
              rolling_friction = 0.1, rolling_model = "constant" }
  local got = r:contact_parameters("m", "m")
  assert(tostring(got.model):match("^linear"), "contact_parameters model: " .. tostring(got.model))
  assert(got.rolling_model == "constant", "contact_parameters rolling_model: " .. tostring(got.rolling_model))
  assert(got.rolling_friction == 0.1, "contact_parameters rolling_friction: " .. tostring(got.rolling_friction))
  has(r:describe(), "rolling_model=constant", "rolling pair")
  r:set_contact("m", "m", { rolling_model = "epsd" })
  assert(r:contact_parameters("m", "m").rolling_model == "epsd", "set_contact did not change the rolling model")
  r:add_particle { position = { 0, 0 }, radius = 0.2e-3, material = "m" }
  -- and the canonical order is said in the header and /scene/effects (effects_check.py)
  r:set { canonical_order = true }
  has(r:describe(), "canonical order: on", "canonical order")
  assert(not plain:find("canonical order", 1, true), "canonical order said when off:\n" .. plain)
  r:output { file = p.out:gsub("%.h5$", "") .. "_rolling.h5" }
  r:run { steps = 1 }
  r:close()
end
-- A later stage's effects reach /scene/effects (effects_check.py): friction,
-- gravity and a moving floor set between runs, and a lid moved by a schedule
-- that starts and ends at rest; the header before the second run says none.
do
  local st = simulation { dimension = 2 }
  st:material { name = "m", density = 1200 }
  st:material { name = "w", density = 0 }
  st:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0 }
  st:contact { "m", "w", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0 }
  st:wall_plane { name = "floor", point = { 0, 0 }, normal = { 0, 1 }, material = "w" }
  st:wall_plane { name = "lid", point = { 0, 5e-3 }, normal = { 0, -1 }, material = "w" }
  st:add_particle { position = { 0, 1e-3 }, radius = 0.2e-3, material = "m" }
  st:output { file = p.out:gsub("%.h5$", "") .. "_stages.h5" }
  st:run { steps = 0 }  -- a run of no steps: its row is the start's, written once
  st:run { steps = 20 }
  has(st:describe(), "rotation: off", "stage one")
  st:set_contact("m", "w", { friction = 0.3 })
  st:gravity { 0, -9.81 }
  st:set_wall("floor", { velocity = { 0.01, 0 } })
  st:schedule { "wall_velocity", wall = "lid", direction = { 0, -1 }, piecewise = { 0, 0, 1e-5, 0.01, 2e-5, 0 } }
  st:run { steps = 20 }
  st:close()
end
-- Bonds turn the particles: the header and /scene/effects say so.
do
  local b = simulation { dimension = 2 }
  b:material { name = "m", density = 1200 }
  b:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0 }
  b:add_particle { position = { 0, 0 }, radius = 0.2e-3, material = "m" }
  b:add_particle { position = { 0.4e-3, 0 }, radius = 0.2e-3, material = "m" }
  b:bond { normal_stiffness = 1e9, shear_stiffness = 1e9, tensile_strength = 1e9, shear_strength = 1e9 }
  has(b:describe(), "rotation: spins integrated (parallel bonds)", "bonds")
  b:output { file = p.out:gsub("%.h5$", "") .. "_bonds.h5" }
  b:run { steps = 1 }
  b:close()
end
-- A periodic scene writes its axis, origin and length on /scene.
do
  local q = simulation { dimension = 3, periodic = { axis = "y", origin = -2e-3, length = 8e-3 } }
  q:material { name = "m", density = 1200 }
  q:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9 }
  q:add_particle { position = { 0, 0, 0 }, radius = 0.2e-3, material = "m", velocity = { 0, 1, 0 } }
  q:output { file = p.out:gsub("%.h5$", "") .. "_periodic.h5" }
  q:run { steps = 1 }
  q:close()
end
-- A turning polyline says how far it has turned: sim:wall's angle, and each
-- snapshot's walls/<name> (effects_check.py).
do
  local t = simulation { dimension = 2 }
  t:material { name = "m", density = 1200 }
  t:contact { "m", "m", model = "linear", k_normal = 2e4, restitution = 0.9, friction = 0 }
  t:wall_polyline { name = "paddle", material = "m", points = { { -1e-3, 0 }, { 1e-3, 0 } },
                    axis_point = { 0, 0 }, angular_velocity = 100 }
  t:add_particle { position = { 0, 5e-3 }, radius = 0.2e-3, material = "m" }
  t:output { file = p.out:gsub("%.h5$", "") .. "_turning.h5" }
  t:run { steps = 40 }
  t:snapshot()
  local turned, want = t:wall("paddle").angle, 100 * t:time()
  assert(want > 0 and math.abs(turned - want) <= 1e-9 * want,
         string.format("sim:wall angle %.17g after %.17g s at 100 rad/s", turned, t:time()))
  t:close()
end
print("effects_check ok")
