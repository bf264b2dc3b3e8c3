-- A sphere settled on a floor under gravity with damped Hertz-Mindlin: its
-- overlap against Hertz's (3 m g / (4 E* sqrt R))^(2/3), the static bias of the
-- law's step-time dashpot (docs/contact_models.md, "What the step-time dashpot
-- costs at rest").
--   build/granule run tools/hm_rest_overlap.lua -D restitution=0.1 -D steps_per_contact=40 -q
local p = parameters {
  restitution = { default = 0.5 },
  steps_per_contact = { default = 40 },
  radius = { default = 1e-3, unit = "m" },
  density = { default = 2500, unit = "kg/m^3" },
  young = { default = 1e8, unit = "Pa" },
  poisson = { default = 0.3 },
  settle = { default = 0.3, unit = "s" },
}
local sim = simulation { dimension = 3, record_contacts = true, steps_per_contact = p.steps_per_contact }
sim:material { name = "m", density = p.density, young = p.young, poisson = p.poisson }
sim:contact { "m", "m", model = "hertz_mindlin", restitution = p.restitution }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 0, 1 }, material = "m" }
local id = sim:add_particle { position = { 0, 0, p.radius }, radius = p.radius, material = "m" }
sim:gravity { 0, 0, -9.81 }
sim:run { duration = p.settle }
local q = sim:particle(id)
local e_star = p.young / (2 * (1 - p.poisson ^ 2))  -- sphere and floor alike
local hertz = (3 * q.mass * 9.81 / (4 * e_star * math.sqrt(p.radius))) ^ (2 / 3)
local overlap = sim:contacts()[1].overlap
print(string.format("restitution %g, %g steps per contact: overlap %.6g m, Hertz %.6g m, ratio %.4f " ..
  "(speed %.2g m/s)", p.restitution, p.steps_per_contact, overlap, hertz, overlap / hertz, math.abs(q.velocity[3])))
