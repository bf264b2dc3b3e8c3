// The work a contact does on its particles against the work its laws take: the
// tangential slip velocity is taken at the point where the torques apply the
// force (levers r - a/2 for a pair, r - a against a wall), so an elastic contact
// that never slides gives back at separation all the energy it took, less what
// its tangential spring still holds as the contact ends. Were the slip taken with
// the full radii and the torques with the shorter levers, a spinning sphere
// would gain energy from a contact with nothing in it that makes any.
#include <catch2/catch.hpp>
#include <cmath>

#include "engine/simulation.hpp"

using namespace granule;

namespace {
constexpr double density = 2500;

struct Case {
  const char* model;
  ParamValues law;
  double young;  // 0 for the linear law
};

// Kinetic energy, translational and rotational (spheres, 2D too), before and
// after one oblique impact of a spinning sphere (r = 1 mm, 1 m/s along and 1
// m/s across the normal) on a sphere of twice its radius at rest, or on a plane.
template <int D>
std::pair<double, double> energies(const Case& c, bool wall, bool batched, double spin) {
  Simulation<D> sim;
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"a", density, c.young, 0.3, 0});
  sim.add_material({"w", 0, c.young, 0.3, 0});
  sim.set_contact("a", "a", c.model, c.law);
  sim.set_contact("a", "w", c.model, c.law);
  sim.set_steps_per_contact(400);
  sim.set_record_contacts(true);
  sim.set_batched_contacts(batched);
  const double r = 1e-3, gap = 1e-3 * r;
  ParticleSpec a;
  a.radius = r, a.material = 0, a.velocity = {1, 1, 0}, a.spin = {0, 0, spin};
  std::vector<std::int64_t> ids;
  if (wall) {
    WallSpec w;
    w.name = "wall", w.material = 1, w.normal = {-1, 0, 0};
    sim.add_wall(w);
    a.position = {-r - gap, 0, 0};
  } else {
    ParticleSpec b;
    b.radius = 2 * r, b.material = 0, b.position = {2 * r, 0, 0};
    a.position = {-r - gap, 0, 0};
    ids.push_back(sim.add_particle(b));
  }
  ids.push_back(sim.add_particle(a));
  auto energy = [&] {
    double e = 0;
    for (const std::int64_t id : ids) {
      const double m = sim.mass(id), rr = sim.radius(id);
      const Triple v = sim.velocity(id), w = sim.spin(id);
      e += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
           0.5 * 0.4 * m * rr * rr * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    return e;
  };
  const double before = energy();
  bool seen = false;
  std::int64_t batched_steps = 0;  // steps whose contact a batched kernel computed
  for (int k = 0; k < 1000000; ++k) {
    sim.advance(1);
    const bool touching = !sim.contacts().empty();
    if (seen && !touching) break;
    seen = seen || touching;
    const auto stats = sim.stats();
    batched_steps += (wall ? stats.contacts_wall_batched : stats.contacts_batched) > 0;
  }
  REQUIRE(seen);
  if (batched) CHECK(batched_steps > 0);
  if (!batched) CHECK(batched_steps == 0);
  return {before, energy()};
}
}  // namespace

TEMPLATE_TEST_CASE_SIG(
    "contact work: an elastic contact that sticks makes no energy, however its "
    "spheres spin",
    "[contact_work]", ((int D), D), 2, 3) {
  // No dashpot (e = 1, no tangential damping) and friction high enough that
  // the contact slides only as its normal force vanishes: nothing in it makes
  // energy. It loses some, the more the faster the spheres spin: what the
  // tangential spring holds as mu N falls to 0 at the end.
  const Case linear{"linear",
                    {{"k_normal", 1e3},
                     {"restitution", 1.0},
                     {"friction", 1e5},
                     {"tangential_damping_ratio", 0.0}},
                    0};
  const Case hertz{"hertz_mindlin", {{"restitution", 1.0}, {"friction", 1e5}}, 2e7};
  for (const Case& c : {linear, hertz})
    for (const bool wall : {false, true})
      for (const bool batched : {false, true})
        for (const double spin : {-6000.0, 0.0, 6000.0}) {
          const auto [before, after] = energies<D>(c, wall, batched, spin);
          INFO(c.model << (wall ? " against a wall" : " between spheres")
                       << (batched ? ", batched" : ", per contact") << ", spin " << spin
                       << " rad/s: E1 / E0 = " << after / before);
          CHECK(after <= before * (1 + 1e-9));
        }
}
