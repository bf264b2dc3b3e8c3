-- A sphere on a floor with twisting resistance and no damping anywhere, let go
-- at half its resting overlap so that its normal load rings, with a small
-- twist (0.01 rad/s) and the twisting spring unloaded. At mu_t where the
-- twist's frequency is half the normal one (0.211 for hertz_mindlin's tangent
-- stiffness, 0.258 for thornton_elastic's secant) a spring that held its torque
-- while the stiffness followed the overlap was pumped to its cap; held as
-- T / sqrt(k_t) (src/contact/rolling.hpp) the twist stays near 0.01 rad/s.
-- Prints the largest twist over 0.1 s (docs/contact_models.md, "Springs whose
-- stiffness follows the overlap"; tests/contact/test_twisting.cpp checks it).
--   build/granule run tools/twist_pump.lua -D model=hertz_mindlin -D mu_t=0.211 -q
--   build/granule run tools/twist_pump.lua -D model=thornton_elastic -D mu_t=0.258 -q
local p = parameters {
  model = { default = "hertz_mindlin", doc = "hertz_mindlin (restitution 1) or thornton_elastic" },
  mu_t = { default = 0.211, min = 0, doc = "twisting friction coefficient" },
}
local e, nu, g, r, rho = 1e8, 0.3, 9.81, 1e-3, 2500
local sim = simulation { dimension = 3 }
sim:material { name = "bead", density = rho, young = e, poisson = nu }
sim:material { name = "floor", density = 0, young = e, poisson = nu }
local law = { "bead", "floor", model = p.model, friction = 0.3, twisting_friction = p.mu_t }
if p.model == "hertz_mindlin" then law.restitution = 1 end
sim:contact(law)
sim:gravity { 0, -g, 0 }
sim:wall_plane { name = "floor", point = { 0, 0, 0 }, normal = { 0, 1, 0 }, material = "floor" }
-- The resting overlap of Hertz's law, m g = 4/3 E* sqrt(r) delta^(3/2).
local mass = rho * 4 / 3 * math.pi * r ^ 3
local e_star = e / (2 * (1 - nu * nu))
local rest = (3 * mass * g / (4 * e_star * math.sqrt(r))) ^ (2 / 3)
local id = sim:add_particle { position = { 0, r - 0.5 * rest, 0 }, radius = r, material = "bead",
                              spin = { 0, 0.01, 0 } }
local largest = 0
sim:every { steps = 1, function(s) largest = math.max(largest, math.abs(s:particle(id).spin[2])) end }
sim:run { duration = 0.1 }
print(string.format("twist_pump: %s, mu_t %g: largest twist %.5g rad/s (started at 0.01)",
                    p.model, p.mu_t, largest))
