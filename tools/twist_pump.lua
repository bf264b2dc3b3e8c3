-- A sphere on a floor with twisting (or rolling) resistance and no damping
-- anywhere, let go at half its resting overlap so that its normal load rings,
-- with a small twist (or rocking spin, about z), 0.01 rad/s, and the spring
-- unloaded. At a coefficient where the spring's mode is half the normal one
-- (twisting: mu_t 0.211 for hertz_mindlin's tangent stiffness, 0.258 for
-- thornton_elastic's secant; rolling: mu_r 0.211 for hertz_mindlin without
-- friction, where the sphere turns about its centre, and near 0.6 for
-- thornton_elastic, where it rocks on the floor) a spring that held its torque
-- while the stiffness followed the overlap was pumped towards its cap; held as
-- torque / sqrt(stiffness) (src/contact/rolling.hpp) the spin stays near
-- 0.01 rad/s. Prints the largest spin about the term's axis over 0.1 s
-- (docs/contact_models.md, "Springs whose stiffness follows the overlap", has
-- the table; tests/contact/test_twisting.cpp and test_rolling.cpp check it).
--   build/granule run tools/twist_pump.lua -D model=hertz_mindlin -D mu=0.211 -q
--   build/granule run tools/twist_pump.lua -D model=thornton_elastic -D mu=0.258 -q
--   build/granule run tools/twist_pump.lua -D term=rolling -D friction=0 -D mu=0.211 -q
--   build/granule run tools/twist_pump.lua -D term=rolling -D model=thornton_elastic -D mu=0.6 -q
local p = parameters {
  model = { default = "hertz_mindlin", doc = "hertz_mindlin (restitution 1) or thornton_elastic" },
  mu = { default = 0.211, min = 0, doc = "the term's friction coefficient: mu_t, or mu_r" },
  term = { default = "twisting", doc = "twisting (spin about the floor's normal) or rolling (about z)" },
  friction = { default = 0.3, min = 0, doc = "Coulomb friction (0: a rolling sphere turns about its centre)" },
}
if p.term ~= "twisting" and p.term ~= "rolling" then
  require("granule.checks").fail("twist_pump", "term", "\"twisting\" or \"rolling\"", p.term)
end
local e, nu, g, r, rho = 1e8, 0.3, 9.81, 1e-3, 2500
local sim = simulation { dimension = 3 }
sim:material { name = "bead", density = rho, young = e, poisson = nu }
sim:material { name = "floor", density = 0, young = e, poisson = nu }
local law = { "bead", "floor", model = p.model, friction = p.friction }
law[p.term .. "_friction"] = p.mu
if p.model == "hertz_mindlin" then law.restitution = 1 end
sim:contact(law)
sim:gravity { 0, -g, 0 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "floor" }
-- The resting overlap of Hertz's law, m g = 4/3 E* sqrt(r) delta^(3/2).
local mass = rho * 4 / 3 * math.pi * r ^ 3
local e_star = e / (2 * (1 - nu * nu))
local rest = (3 * mass * g / (4 * e_star * math.sqrt(r))) ^ (2 / 3)
local axis = p.term == "twisting" and 2 or 3
local spin = { 0, 0, 0 }
spin[axis] = 0.01
local id = sim:add_particle { position = { 0, r - 0.5 * rest, 0 }, radius = r, material = "bead", spin = spin }
local largest = 0
sim:every { steps = 1, function(s) largest = math.max(largest, math.abs(s:particle(id).spin[axis])) end }
sim:run { duration = 0.1 }
print(string.format("twist_pump: %s, %s, mu %g: largest %s %.5g rad/s (started at 0.01)",
                    p.term, p.model, p.mu, p.term == "twisting" and "twist" or "rocking spin", largest))
