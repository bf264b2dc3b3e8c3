// Thornton's elastic law is elastic: an impact may lose energy to micro-slip
// but never gain it. Eq. 6.11 moves the reversal points T* and T** by mu dN a
// step; far above mu = 1 they run out to the Coulomb limit and the unloading
// branch does work (an elastic impact gains energy), so friction is bounded
// at ThorntonElastic::friction_limit, where no impact of these (angles 2-85
// degrees, walls and spheres, nu 0 and 0.49) gains more than the time step's
// own error on an elastic impact (5e-4 allowed at 160 steps a contact).
#include <catch2/catch.hpp>
#include <cmath>

#include "contact/thornton_elastic.hpp"
#include "core/errors.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {

// Kinetic energy after / before a 1 m/s impact on a wall at `angle_deg` from its normal.
double energy_ratio(double friction, double angle_deg, double poisson, bool wall) {
  Simulation<3> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"g", 2500, 1e8, poisson, 0});
  sim.set_contact("g", "g", "thornton_elastic", {{"friction", friction}});
  sim.set_steps_per_contact(160);
  sim.set_record_contacts(true);
  const double r = 1e-3, a = angle_deg * M_PI / 180;
  ParticleSpec p;
  p.radius = r;
  p.material = 0;
  p.position = {-r - 1e-6, 0, 0};
  p.velocity = {std::cos(a), std::sin(a), 0};
  if (wall) {
    WallSpec w;
    w.name = "wall";
    w.material = 0;
    w.normal = {-1, 0, 0};
    sim.add_wall(w);
    sim.add_particle(p);
  } else {
    p.position = {-r - 0.5e-6, 0, 0};
    p.velocity = {0.5 * std::cos(a), 0.5 * std::sin(a), 0};
    sim.add_particle(p);
    p.position = {r + 0.5e-6, 0, 0};
    p.velocity = {-0.5 * std::cos(a), -0.5 * std::sin(a), 0};
    sim.add_particle(p);
  }
  sim.prepare();
  auto energy = [&] {
    const GlobalStats s = sim.stats();
    return s.kinetic_translational + s.kinetic_rotational;
  };
  const double before = energy();
  bool seen = false;
  for (int k = 0; k < 1000000; ++k) {
    sim.advance(1);
    const bool touching = !sim.contacts().empty();
    if (seen && !touching) break;
    seen = seen || touching;
  }
  REQUIRE(seen);
  return energy() / before;
}

}  // namespace

TEST_CASE(
    "thornton: an elastic impact gains no energy up to the friction limit, and mu above it "
    "is refused",
    "[thornton]") {
  const double mu = ThorntonElastic::friction_limit;
  double largest = 0;
  for (const bool wall : {true, false})
    for (const double poisson : {0.0, 0.49})
      for (const double angle : {2.0, 5.0, 45.0, 85.0}) {
        const double ratio = energy_ratio(mu, angle, poisson, wall);
        INFO("wall " << wall << ", nu " << poisson << ", angle " << angle);
        CHECK(ratio < 1 + 5e-4);
        largest = std::max(largest, ratio);
      }
  CHECK(largest > 0.99);  // near-normal impacts lose almost nothing
  Simulation<3> sim;
  sim.add_material({"g", 2500, 1e8, 0.3, 0});
  CHECK_THROWS_WITH(sim.set_contact("g", "g", "thornton_elastic", {{"friction", 30.0}}),
                    Catch::Contains("friction"));
  CHECK_THROWS_WITH(sim.set_contact("g", "g", "thornton_jkr", {{"friction", 11.0}}),
                    Catch::Contains("friction"));
}
