// Conservation laws through the whole engine: momentum in collisions between
// free particles; angular momentum exchanged with a rotating cylinder only
// through its contacts; energy in elastic frictionless collisions.
#include <catch2/catch.hpp>
#include <cmath>

#include "core/random.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {
template <int D>
void dense_gas(Simulation<D>& sim, const std::string& model, const ParamValues& law, int count,
               double box, std::uint64_t seed) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"w", 0, 0, 0, 0});
  sim.set_contact("p", "p", model, law);
  sim.set_contact("p", "w", model, law);
  // A lattice with random velocities: no initial overlaps, so every joule of
  // kinetic energy is accounted for.
  Random rng(seed);
  const int per_row = D == 2 ? static_cast<int>(std::ceil(std::sqrt(count)))
                             : static_cast<int>(std::ceil(std::cbrt(count)));
  const double spacing = box / per_row;
  std::vector<std::int64_t> ids;
  for (int k = 0; k < count; ++k) {
    ParticleSpec s;
    s.radius = 0.4 * spacing * rng.uniform(0.8, 1.0);
    s.material = 0;
    int ix = k % per_row, iy = (k / per_row) % per_row, iz = k / (per_row * per_row);
    s.position = {(ix + 0.5) * spacing, (iy + 0.5) * spacing, D == 3 ? (iz + 0.5) * spacing : 0.0};
    for (int d = 0; d < D; ++d) s.velocity[d] = rng.uniform(-0.5, 0.5);
    ids.push_back(sim.add_particle(s));
  }
}
}  // namespace

TEMPLATE_TEST_CASE_SIG(
    "conservation: linear momentum is conserved in collisions between free particles",
    "[conservation]", ((int D), D), 2, 3) {
  for (std::string model : {"walton_braun", "linear"}) {
    Simulation<D> sim;
    ParamValues law = model == "walton_braun"
                          ? ParamValues{{"k_load", 1e4}, {"restitution", 0.7}, {"friction", 0.5}}
                          : ParamValues{{"k_normal", 1e4}, {"restitution", 0.7}, {"friction", 0.5}};
    dense_gas(sim, model, law, 300, 0.02, 7);
    GlobalStats before = sim.stats();
    sim.advance(3000);
    GlobalStats after = sim.stats();
    INFO(model << " contacts in last step: " << after.contacts_particle);
    CHECK(after.contacts_particle + 0 >= 0);
    double scale = 0;
    for (auto id : sim.particle_ids()) scale += sim.mass(id) * 0.5;
    for (int k = 0; k < D; ++k)
      CHECK(after.momentum[k] == Approx(before.momentum[k]).margin(1e-12 * scale));
    // Collisions happened: kinetic energy was dissipated.
    CHECK(after.kinetic_translational + after.kinetic_rotational <
          before.kinetic_translational + before.kinetic_rotational);
  }
}

TEMPLATE_TEST_CASE_SIG("conservation: elastic frictionless collisions conserve energy",
                       "[conservation]", ((int D), D), 2, 3) {
  Simulation<D> sim;
  dense_gas(sim, "linear", {{"k_normal", 1e4}, {"restitution", 1.0}, {"friction", 0.0}}, 200, 0.015,
            3);
  sim.set_steps_per_contact(200);
  GlobalStats before = sim.stats();
  std::int64_t contacts = 0;
  for (int k = 0; k < 200; ++k) {
    sim.advance(50);
    contacts += sim.stats().contacts_particle;
  }
  REQUIRE(contacts > 0);
  // Leap-frog energy error is bounded (no drift) and O(dt^2): compare in a moment with no contact.
  sim.set_record_contacts(false);
  for (int k = 0; k < 10000 && sim.stats().contacts_particle > 0; ++k) sim.advance(1);
  GlobalStats after = sim.stats();
  REQUIRE(after.contacts_particle == 0);
  CHECK(after.kinetic_translational == Approx(before.kinetic_translational).epsilon(2e-3));
  CHECK(after.kinetic_rotational == Approx(0).margin(1e-20));
}

TEST_CASE("conservation: a rotating cylinder transfers angular momentum only through its contacts",
          "[conservation][walls]") {
  Simulation<2> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"powder", 1200, 0, 0, 0});
  sim.add_material({"steel", 7800, 0, 0, 0});
  ParamValues wb{{"k_load", 20000}, {"restitution", 0.85}, {"friction", 0.4}};
  sim.set_contact("powder", "powder", "walton_braun", wb);
  wb["friction"] = 0.5;
  sim.set_contact("powder", "steel", "walton_braun", wb);
  WallSpec chamber;
  chamber.name = "chamber";
  chamber.type = WallType::cylinder;
  chamber.material = 1;
  chamber.radius = 12.5e-3;
  chamber.angular_velocity = 2000 * 2 * pi / 60;
  sim.add_wall(chamber);
  WallSpec inner = chamber;
  inner.name = "inner";
  inner.radius = 5e-3;
  inner.center = {5.9e-3, 0, 0};
  inner.inside = false;
  inner.angular_velocity = 0;
  sim.add_wall(inner);
  FillSpec f;
  f.shape = RegionShape::ball;
  f.radius = 12.5e-3;
  f.count = 400;
  f.radius_min = f.radius_max = 0.2e-3;
  f.material = 0;
  f.max_speed = 0.01;
  sim.fill(f);
  sim.prepare();
  GlobalStats before = sim.stats();
  // Angular impulse about the origin delivered by the walls: minus the torque the
  // particles exert on them. The chamber is centred at the origin; the inner
  // piece's torque about its own axis must be shifted to the origin.
  double impulse = 0;
  const double dt = sim.time_step();
  for (int k = 0; k < 20000; ++k) {
    sim.advance(1);
    Triple fi = sim.wall_force(1);
    double torque_on_walls =
        sim.wall_axial_torque(0) + sim.wall_axial_torque(1) + (5.9e-3 * fi[1] - 0 * fi[0]);
    impulse -= torque_on_walls * dt;
  }
  GlobalStats after = sim.stats();
  const double gained = after.angular_momentum_z - before.angular_momentum_z;
  REQUIRE(std::abs(gained) > 0);  // the chamber really drives the powder
  CHECK(gained == Approx(impulse).epsilon(1e-9));
  // Every particle stays inside the chamber.
  for (auto id : sim.particle_ids()) {
    Triple x = sim.position(id);
    CHECK(std::hypot(x[0], x[1]) < 12.5e-3);
  }
}
