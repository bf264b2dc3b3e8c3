// The parallel bond (contact/parallel_bond.hpp) through the engine, against the
// beam closed forms of Potyondy and Cundall (2004): a bond of radius R_b
// (A = pi R_b^2, I = pi R_b^4 / 4, J = pi R_b^4 / 2) between two particles
// moved relative to each other by a small prescribed amount carries
//   normal:  F_n = k_n A dx,     shear:   F_s = k_s A dy,
//   twist:   M_t = k_s J theta,  bending: M_b = k_n I theta.
// The motion is prescribed by inertia: particles of density 1e20 kg/m^3 given
// a velocity or spin keep it to 1e-20 relative while the bond loads them.
// Breaking: pulled apart at a constant speed, the bond breaks at the step where
// F_n / A first reaches the tensile strength. Free flight: the loads are equal
// and opposite and their torques cancel, so linear and angular momentum are
// conserved to round-off; the bond stores its energy elastically, so the
// total energy's error is the leap-frog's, which shrinks with dt.
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "core/errors.hpp"
#include "engine/simulation.hpp"
#include "io/checkpoint.hpp"

using namespace granule;

namespace {

constexpr double radius = 1e-3;   // m
constexpr double k_normal = 1e9;  // Pa/m
constexpr double k_shear = 4e8;   // Pa/m
const double area = pi * radius * radius, inertia = 0.25 * pi * std::pow(radius, 4),
             polar = 0.5 * pi * std::pow(radius, 4);

BondSpec spec(double tensile = 1e15, double shear = 1e15, double gap = 0) {
  BondSpec s;
  s.gap = gap;
  s.normal_stiffness = k_normal, s.shear_stiffness = k_shear;
  s.tensile_strength = tensile, s.shear_strength = shear;
  return s;
}

// Particles a at the origin and b at (2r + gap, 0[, 0]), bonded; the normal
// from b to a is -x.
template <int D>
std::unique_ptr<Simulation<D>> bonded_pair(double density, double dt, const ParticleSpec& a,
                                           const ParticleSpec& b, const BondSpec& s) {
  auto sim = std::make_unique<Simulation<D>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", density, 0, 0, 0});
  sim->set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 1.0}});
  sim->set_time_step(dt);
  sim->add_particle(a);
  sim->add_particle(b);
  REQUIRE(sim->create_bonds(s) == 1);
  return sim;
}

ParticleSpec particle(const Triple& x, const Triple& v = {}, const Triple& w = {}) {
  ParticleSpec p;
  p.position = x, p.velocity = v, p.spin = w;
  p.radius = radius, p.material = 0;
  return p;
}

double norm(const Triple& t) {
  return std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
}

// One mode: b (and a, for the rotations) moving as given for `steps` steps.
template <int D>
const BondLoad<D>& loaded(std::unique_ptr<Simulation<D>>& sim, std::int64_t steps) {
  sim->advance(steps);
  REQUIRE(sim->bond_counts().intact == 1);
  return sim->bonds().load[0];
}

constexpr double heavy = 1e20, dt = 1e-6;
constexpr std::int64_t steps = 1000;

}  // namespace

TEMPLATE_TEST_CASE_SIG("bond: stiffness in each mode against the beam closed forms", "[bond]",
                       ((int D), D), 2, 3) {
  const double speed = 1e-5, spin = 1e-2;  // m/s, rad/s: dx = 1e-8 m, theta = 1e-5 rad
  SECTION("normal: F_n = k_n A dx, pulling a towards b") {
    auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}),
                              particle({2 * radius, 0, 0}, {speed, 0, 0}), spec());
    const BondLoad<D>& f = loaded(sim, steps);
    // The prescribed stretch when the last step's forces were taken, before its
    // move (the bond made at the start has seen no motion on the first step);
    // the positions (2e-3 m advanced by 1e-11 m a step) hold it only to their
    // round-off.
    const double dx = speed * dt * (steps - 1);
    CHECK(sim->position(1)[0] - sim->position(0)[0] - 2 * radius ==
          Approx(dx + speed * dt).epsilon(1e-6));
    CHECK(-f.normal == Approx(k_normal * area * dx).epsilon(1e-9));  // tension
    // The force the engine applied: on a towards b (+x), on b the opposite.
    CHECK(sim->force(0)[0] == Approx(k_normal * area * dx).epsilon(1e-9));
    CHECK(sim->force(1)[0] == -sim->force(0)[0]);
    CHECK(f.shear.norm() == 0);
  }
  SECTION("shear: F_s = k_s A dy, on a along b's motion") {
    auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}),
                              particle({2 * radius, 0, 0}, {0, speed, 0}), spec());
    const BondLoad<D>& f = loaded(sim, steps);
    const double dy = sim->position(1)[1] - sim->position(0)[1] - speed * dt;  // at the last forces
    CHECK(f.shear.norm() == Approx(k_shear * area * dy).epsilon(1e-9));
    CHECK(f.shear[1] > 0);
    CHECK(sim->force(0)[1] == Approx(k_shear * area * dy).epsilon(1e-9));
    // The axis turned by dy / 2r, stretching the bond by dy^2 / 4r (second order).
    CHECK(std::abs(f.normal) < 1.01 * k_normal * area * dy * dy / (4 * radius));
  }
  SECTION("bending: M_b = k_n I theta, the two turned opposite ways") {
    auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}, {}, {0, 0, -spin / 2}),
                              particle({2 * radius, 0, 0}, {}, {0, 0, spin / 2}), spec());
    const BondLoad<D>& f = loaded(sim, steps);
    const double theta = spin * dt * (steps - 1);  // at the last forces
    CHECK(std::sqrt(Dim<D>::spin_sq(f.bending)) ==
          Approx(k_normal * inertia * theta).epsilon(1e-9));
    // Turning a's side of the bond with b's: on a about +z.
    if constexpr (D == 3)
      CHECK(f.bending[2] > 0);
    else
      CHECK(f.bending > 0);
    // The spins' change under the moment (1e-20 of them) is all that shears or stretches it.
    CHECK(f.shear.norm() * radius < 1e-12 * k_normal * inertia * theta);
    CHECK(std::abs(f.normal) * radius < 1e-12 * k_normal * inertia * theta);
  }
  if constexpr (D == 3) {
    SECTION("twist: M_t = k_s J theta, about the bond's axis") {
      auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}, {}, {-spin / 2, 0, 0}),
                                particle({2 * radius, 0, 0}, {}, {spin / 2, 0, 0}), spec());
      const BondLoad<D>& f = loaded(sim, steps);
      const double theta = spin * dt * (steps - 1);  // at the last forces
      CHECK(std::abs(f.twist) == Approx(k_shear * polar * theta).epsilon(1e-9));
      CHECK(f.bending.norm() == 0);
      CHECK(f.shear.norm() == 0);
    }
  }
}

TEMPLATE_TEST_CASE_SIG("bond: pulled apart slowly it breaks at the tensile strength", "[bond]",
                       ((int D), D), 2, 3) {
  const double speed = 1e-2, strength = 123456.7;  // m/s, Pa: 12345.67 increments to break
  auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}),
                            particle({2 * radius, 0, 0}, {speed, 0, 0}), spec(strength, 1e15));
  const double increment = k_normal * area * speed * dt;  // N a step
  const double breaking_force = strength * area;
  double last_intact = 0;
  std::int64_t step = 0;
  while (sim->bond_counts().intact == 1 && step < 100000) {
    last_intact = -sim->bonds().load[0].normal;
    sim->advance(1), ++step;
  }
  REQUIRE(sim->bond_counts().broken == 1);
  const double at_break = -sim->bonds().load[0].normal;
  CHECK(last_intact < breaking_force);
  CHECK(at_break >= breaking_force);
  CHECK(at_break - breaking_force < increment);
  // (The first step's forces find the bond as made: it stretches from the second.)
  CHECK(step == 1 + static_cast<std::int64_t>(std::ceil(breaking_force / increment)));
  // The load of the breaking step is not applied, nor any after it.
  CHECK(norm(sim->force(0)) == 0);
  sim->advance(10);
  CHECK(norm(sim->force(0)) == 0);
  CHECK(sim->bond_counts().broken == 1);
}

TEMPLATE_TEST_CASE_SIG("bond: sheared past its strength it breaks and the contact law acts alone",
                       "[bond]", ((int D), D), 2, 3) {
  const double speed = 1e-2, strength = 1e5;
  auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}),
                            particle({2 * radius, 0, 0}, {0, speed, 0}), spec(1e15, strength));
  std::int64_t step = 0;
  while (sim->bond_counts().intact == 1 && step < 100000) sim->advance(1), ++step;
  REQUIRE(sim->bond_counts().broken == 1);
  const BondLoad<D>& f = sim->bonds().load[0];
  const double increment = k_shear * area * speed * dt;
  CHECK(f.shear.norm() >= strength * area);
  CHECK(f.shear.norm() - strength * area < 1.001 * increment);
}

namespace {
// Linear momentum, angular momentum about the origin (3 components; 2D: z) and
// energy (kinetic and the bond's strain) of a scene's particles.
template <int D>
struct Totals {
  Triple momentum{}, angular{};
  double energy = 0;
};
// Leap-frog's velocities lie half a step off its positions; the kinetic energy
// is taken from the mean of the velocities either side of the step whose
// bond load the engine holds (`before`: the velocities and spins before it).
template <int D>
Totals<D> totals(const Simulation<D>& sim, const std::array<Triple, 4>& before) {
  Totals<D> t;
  for (std::int64_t id : {0, 1}) {
    const Triple x = sim.position(id), v_now = sim.velocity(id), w_now = sim.spin(id);
    Triple v, w;
    for (int a = 0; a < 3; ++a)
      v[a] = 0.5 * (v_now[a] + before[2 * id][a]), w[a] = 0.5 * (w_now[a] + before[2 * id + 1][a]);
    const double m = sim.mass(id), i = sphere_inertia(m, sim.radius(id));
    // Leap-frog conserves the momenta of x^(n+1) and v^(n+1/2) exactly: those now.
    for (int a = 0; a < 3; ++a) t.momentum[a] += m * v_now[a];
    const Triple xv = {x[1] * v_now[2] - x[2] * v_now[1], x[2] * v_now[0] - x[0] * v_now[2],
                       x[0] * v_now[1] - x[1] * v_now[0]};
    for (int a = 0; a < 3; ++a) t.angular[a] += m * xv[a] + i * w_now[a];
    t.energy += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
                0.5 * i * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  }
  t.energy += bond_energy<D>(sim.bonds().properties[0], sim.bonds().load[0]);
  return t;
}

// A pair spinning and vibrating in free flight across a gap its contact law
// never closes; the largest relative energy error over `duration`.
template <int D>
double free_flight(double step, double duration, bool check_momenta) {
  const double gap = 2e-5;
  auto sim = bonded_pair<D>(2500, step, particle({0, 0, 0}, {0.01, 0.02, 0.0}, {30, -20, 10}),
                            particle({2 * radius + gap / 2, 0, 0}, {-0.02, 0.0, 0.03}, {-5, 5, 40}),
                            spec(1e15, 1e15, gap));
  auto state = [&] {
    return std::array<Triple, 4>{sim->velocity(0), sim->spin(0), sim->velocity(1), sim->spin(1)};
  };
  std::array<Triple, 4> before = state();
  sim->advance(1);
  const Totals<D> start = totals(*sim, before);
  double scale_p = 0, scale_l = 0;
  for (int a = 0; a < 3; ++a)
    scale_p = std::max(scale_p, std::abs(start.momentum[a])),
    scale_l = std::max(scale_l, std::abs(start.angular[a]));
  double worst = 0;
  const auto n = static_cast<std::int64_t>(std::llround(duration / step));
  for (std::int64_t k = 1; k < n; ++k) {
    before = state();
    sim->advance(1);
    const Totals<D> now = totals(*sim, before);
    if (check_momenta)
      for (int a = 0; a < 3; ++a) {
        REQUIRE(std::abs(now.momentum[a] - start.momentum[a]) <= 1e-13 * scale_p);
        REQUIRE(std::abs(now.angular[a] - start.angular[a]) <= 1e-12 * scale_l);
      }
    worst = std::max(worst, std::abs(now.energy - start.energy) / start.energy);
  }
  REQUIRE(sim->bond_counts().intact == 1);
  REQUIRE(sim->stats().contacts_particle == 0);
  return worst;
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("bond: a bonded pair in free flight conserves momenta and energy", "[bond]",
                       ((int D), D), 2, 3) {
  // omega = sqrt(k_n A / m*) ~ 2.4e4 rad/s: 1e-6 s is ~260 steps a period.
  const double coarse = free_flight<D>(1e-6, 2e-3, true);
  const double fine = free_flight<D>(0.5e-6, 2e-3, false);
  INFO("energy error " << coarse << " at dt, " << fine << " at dt / 2");
  CHECK(coarse < 1e-3);
  CHECK(fine < 0.35 * coarse);  // second order: the integrator's error, not the bond's
}

TEMPLATE_TEST_CASE_SIG("bond: bad parameters and a step too long for the bonds are refused",
                       "[bond]", ((int D), D), 2, 3) {
  auto sim = bonded_pair<D>(2500, 1e-6, particle({0, 0, 0}), particle({2 * radius, 0, 0}), spec());
  auto refused = [&](BondSpec s, const char* needle) {
    try {
      sim->create_bonds(s);
      FAIL("accepted: " << needle);
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Contains(needle));
    }
  };
  BondSpec s = spec();
  s.normal_stiffness = -1;
  refused(s, "'normal_stiffness'");
  s = spec(), s.shear_stiffness = NAN;
  refused(s, "'shear_stiffness'");
  s = spec(0);
  refused(s, "'tensile_strength'");
  s = spec(1, INFINITY);
  refused(s, "'shear_strength'");
  s = spec(), s.radius_multiplier = 0;
  refused(s, "'radius_multiplier'");
  s = spec(), s.gap = -1e-9;
  refused(s, "'gap'");
  s = spec(), s.gap = 1;
  refused(s, "'gap'");
  // The pair is bonded already: a second call adds nothing.
  CHECK(sim->create_bonds(spec()) == 0);
  CHECK(sim->bond_counts().intact == 1);
  // A bond so stiff that the step cannot resolve it.
  Simulation<D> other;
  other.set_warning_handler([](const std::string&) {});
  other.add_material({"p", 2500, 0, 0, 0});
  other.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 1.0}});
  other.set_time_step(1e-6);
  other.add_particle(particle({0, 0, 0}));
  other.add_particle(particle({2 * radius, 0, 0}));
  s = spec(), s.normal_stiffness = 1e16;
  try {
    other.create_bonds(s);
    FAIL("a bond beyond the stability limit was made");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("stability limit"));
  }
  CHECK(other.bond_counts().intact == 0);
  // A bond made under a short step, then the step lengthened past its limit (sim:set).
  s = spec(), s.normal_stiffness = 1e12;
  REQUIRE(other.create_bonds(s) == 1);
  other.set_time_step(3e-5);  // within the contact's limit, 20 times the bonds'
  try {
    other.advance(1);
    FAIL("a time step beyond the bonds' stability limit was taken");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("bonds' stability limit"));
  }
}

namespace {
// A bonded square (2D: 4 x 3) or block (3D: 3 x 3 x 2) of touching spheres
// thrown at a floor: the impact breaks some of its bonds.
template <int D>
void bonded_block(Simulation<D>& sim) {
  sim.set_warning_handler([](const std::string&) {});
  sim.add_material({"p", 2500, 0, 0, 0});
  sim.add_material({"floor", 0, 0, 0, 0});
  ParamValues law{{"k_normal", 1e4}, {"restitution", 0.5}, {"friction", 0.3}};
  sim.set_contact("p", "p", "linear", law);
  sim.set_contact("p", "floor", "linear", law);
  WallSpec w;
  w.name = "floor", w.material = 1, w.normal = {0, 1, 0};
  sim.add_wall(w);
  const int nz = D == 3 ? 2 : 1;
  for (int ix = 0; ix < (D == 3 ? 3 : 4); ++ix)
    for (int iy = 0; iy < 3; ++iy)
      for (int iz = 0; iz < nz; ++iz) {
        ParticleSpec p =
            particle({2 * radius * ix, 1.2 * radius + 2 * radius * iy, 2 * radius * iz},
                     {0.3 * ix, -0.3, 0.05 * iz});
        sim.add_particle(p);
      }
  BondSpec s = spec(1e4, 1e4, 1e-6 * radius);
  s.normal_stiffness = 1e9, s.shear_stiffness = 5e8;
  REQUIRE(sim.create_bonds(s) == (D == 3 ? 33 : 17));  // the lattice's nearest neighbours
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("bond: a run continued from a checkpoint is bit-identical, bonds and all",
                       "[bond][checkpoint]", ((int D), D), 2, 3) {
  Simulation<D> whole;
  bonded_block(whole);
  whole.advance(150);  // into the impact
  // Through the file, as a restart reads it.
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("granule_bond_" + std::to_string(getpid()) + "_" + std::to_string(D) + ".chk.h5"))
          .string();
  io::write_checkpoint(path, whole.save_state(), {{"scene", "bonds"}});
  const StateBlob saved = io::read_checkpoint(path);
  std::remove(path.c_str());
  const auto counts_then = whole.bond_counts();
  whole.advance(3000);
  Simulation<D> resumed;
  bonded_block(resumed);
  resumed.load_state(saved);
  CHECK(resumed.bond_counts().intact == counts_then.intact);
  resumed.advance(3000);
  const auto x = whole.flat_state(), y = resumed.flat_state();
  CHECK(x.position == y.position);
  CHECK(x.velocity == y.velocity);
  CHECK(x.spin == y.spin);
  const auto& a = whole.bonds();
  const auto& b = resumed.bonds();
  REQUIRE(a.size() == b.size());
  CHECK(a.broken == b.broken);
  for (std::size_t k = 0; k < a.size(); ++k) {
    CHECK(a.load[k].normal == b.load[k].normal);
    CHECK(a.load[k].shear == b.load[k].shear);
    CHECK(a.load[k].bending == b.load[k].bending);
  }
  // The impact broke some bonds, not all.
  CHECK(whole.bond_counts().broken > 0);
  CHECK(whole.bond_counts().intact > 0);
  // A damaged bond entry is refused by name.
  StateBlob bad = saved;
  bad.integers.at("bonds.broken")[0] = 2;
  Simulation<D> target;
  bonded_block(target);
  CHECK_THROWS_WITH(target.load_state(bad), Catch::Contains("'bonds.broken'"));
  bad = saved;
  bad.doubles.at("bonds.properties").pop_back();
  CHECK_THROWS_WITH(target.load_state(bad), Catch::Contains("'bonds.properties'"));
}

TEMPLATE_TEST_CASE_SIG("bond: the bonds' loads are summed in bond order whatever the threads",
                       "[bond][parallel]", ((int D), D), 2, 3) {
  Simulation<D> one, two;
  bonded_block(one);
  bonded_block(two);
  two.set_threads(2);
  two.set_parallel_thresholds(1, 1);  // every loop parallel, even for this small block
  one.advance(2000);
  two.advance(2000);
  const auto x = one.flat_state(), y = two.flat_state();
  CHECK(x.position == y.position);
  CHECK(x.velocity == y.velocity);
  CHECK(x.spin == y.spin);
  CHECK(one.bonds().broken == two.bonds().broken);
  CHECK(one.bond_counts().broken > 0);
  // The records say the same as the counts, in id order.
  const auto records = one.bond_records();
  std::int64_t broken = 0;
  for (std::size_t k = 0; k < records.size(); ++k) {
    broken += records[k].broken;
    CHECK(records[k].id_a < records[k].id_b);
    if (k)
      CHECK(std::make_pair(records[k - 1].id_a, records[k - 1].id_b) <
            std::make_pair(records[k].id_a, records[k].id_b));
  }
  CHECK(broken == one.bond_counts().broken);
}

namespace {
// A bonded pair turning as one body at omega about z through its centre: the
// largest relative energy error over `turns` turns, and the change of the
// distance between the centres averaged over the first and the last turn.
template <int D>
std::pair<double, double> turning_pair(double omega, double step, int turns) {
  const double v = omega * radius;
  auto sim = bonded_pair<D>(2500, step, particle({0, 0, 0}, {0, -v, 0}, {0, 0, omega}),
                            particle({2 * radius, 0, 0}, {0, v, 0}, {0, 0, omega}), spec());
  auto state = [&] {
    return std::array<Triple, 4>{sim->velocity(0), sim->spin(0), sim->velocity(1), sim->spin(1)};
  };
  auto distance = [&] {
    const Triple a = sim->position(0), b = sim->position(1);
    return std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
  };
  const auto per_turn = static_cast<std::int64_t>(std::llround(2 * pi / (omega * step)));
  std::array<Triple, 4> before = state();
  sim->advance(1);
  const double e0 = totals(*sim, before).energy;
  double worst = 0, first = 0, last = 0;
  for (int turn = 0; turn < turns; ++turn)
    for (std::int64_t k = 0; k < per_turn; ++k) {
      before = state();
      sim->advance(1);
      worst = std::max(worst, std::abs(totals(*sim, before).energy - e0) / e0);
      if (turn == 0) first += distance() / static_cast<double>(per_turn);
      if (turn == turns - 1) last += distance() / static_cast<double>(per_turn);
    }
  REQUIRE(sim->bond_counts().intact == 1);
  return {worst, last - first};
}
}  // namespace

TEMPLATE_TEST_CASE_SIG("bond: a pair turning as one body keeps its length and its energy", "[bond]",
                       ((int D), D), 2, 3) {
  // Leap-frog's velocities lag the positions by half a step; taken along the
  // current normal they read a closing speed of omega^2 |d| dt / 2, and the
  // incremental F_n shortened the bond by ~pi omega dt |d| a turn (12 um here)
  // while the energy rose turn by turn.
  const auto [energy_error, shortening] = turning_pair<D>(2000, 1e-6, 10);
  INFO("energy error " << energy_error << ", mean distance changed by " << shortening << " m");
  CHECK(energy_error < 2e-3);
  CHECK(std::abs(shortening) < 1e-7);
}

TEST_CASE("bond: shear and bending turn with a pair spinning about its axis", "[bond]") {
  // b is moved along y (shear) and turned about z against a (bending), then the
  // two spin together about the line through their centres, u: a quarter turn
  // later the loads, fixed in the bodies, are turned to u x F_s and u x M_b.
  auto sim = bonded_pair<3>(heavy, dt, particle({0, 0, 0}, {}, {0, 0, -0.5}),
                            particle({2 * radius, 0, 0}, {0, 1e-3, 0}, {0, 0, 0.5}), spec());
  sim->advance(steps);
  const double omega = 200;
  const Triple a = sim->position(0), b = sim->position(1);
  Vec<3> u(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
  u.normalize();
  sim->set_velocity(1, {0, 0, 0});
  sim->set_spin(0, {omega * u[0], omega * u[1], omega * u[2]});
  sim->set_spin(1, {omega * u[0], omega * u[1], omega * u[2]});
  // The next step's forces still count the last step's motion, made with the
  // velocities and spins set before: the loads as they stand after it.
  sim->advance(1);
  const Vec<3> shear = sim->bonds().load[0].shear, bending = sim->bonds().load[0].bending;
  REQUIRE(shear[1] > 0);
  REQUIRE(bending[2] != 0);
  const auto quarter = static_cast<std::int64_t>(std::llround(0.5 * pi / (omega * dt)));
  sim->advance(quarter);
  const BondLoad<3>& f = sim->bonds().load[0];
  const Vec<3> shear_turned = u.cross(shear), bending_turned = u.cross(bending);
  INFO("shear before " << shear.transpose() << ", after " << f.shear.transpose());
  INFO("bending before " << bending.transpose() << ", after " << f.bending.transpose());
  CHECK((f.shear - shear_turned).norm() < 1e-3 * shear.norm());
  CHECK((f.bending - bending_turned).norm() < 1e-3 * bending.norm());
}

TEMPLATE_TEST_CASE_SIG("bond: a removed particle's bonds break at once", "[bond]", ((int D), D), 2,
                       3) {
  auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}), particle({2 * radius, 0, 0}), spec());
  sim->advance(1);
  REQUIRE(sim->bond_counts().intact == 1);
  sim->remove_particle(sim->particle_ids().back());
  CHECK(sim->bond_counts().intact == 0);  // not only at the next step's apply_bonds
  CHECK(sim->bond_counts().broken == 1);
  sim->advance(1);
  CHECK(sim->bond_counts().broken == 1);
}

TEMPLATE_TEST_CASE_SIG("bond: a particle moved away by set_position breaks its bonds", "[bond]",
                       ((int D), D), 2, 3) {
  auto sim = bonded_pair<D>(heavy, dt, particle({0, 0, 0}), particle({2 * radius, 0, 0}), spec());
  sim->advance(1);
  REQUIRE(sim->bond_counts().intact == 1);
  const std::int64_t first = sim->particle_ids().front(), moved = sim->particle_ids().back();
  // A small move (a dilation, a nudge) keeps the bond and its load.
  sim->set_position(moved, {2.5 * radius, 0, 0});
  sim->advance(1);
  CHECK(sim->bond_counts().intact == 1);
  // The pair moved one particle at a time, far, as a rigid cluster: kept.
  const Triple a = sim->position(first), b = sim->position(moved);
  sim->set_position(first, {a[0] + 50 * radius, a[1], a[2]});
  sim->set_position(moved, {b[0] + 50 * radius, b[1], b[2]});
  sim->advance(1);
  CHECK(sim->bond_counts().intact == 1);
  // One moved away, its gap widened by more than the smaller radius: the bond holds
  // nothing and breaks before the next step's forces.
  sim->set_position(moved, {b[0] + 100 * radius, b[1], b[2]});
  CHECK(sim->bond_counts().intact == 1);
  sim->advance(1);
  CHECK(sim->bond_counts().intact == 0);
  CHECK(sim->bond_counts().broken == 1);
}

TEMPLATE_TEST_CASE_SIG(
    "bond: velocities a script sets between steps load the bond only with the motion they make",
    "[bond]", ((int D), D), 2, 3) {
  // A sphere hanging from a fixed one by its bond, damped by multiplying its
  // velocity (and spin) by c after every step: it settles where the bond
  // carries its weight, m g / (k_n A) of stretch, whatever c. Reading the
  // scaled velocity as the motion of the step before, the bond would record
  // only c of every step's stretch and settle at 1 / c of it.
  const double g = 100, c = 0.9;
  ParticleSpec top = particle({0, 0, 0});
  top.fixed = true;
  auto sim = bonded_pair<D>(2.5e6, 2e-5, top, particle({2 * radius, 0, 0}), spec());
  sim->set_gravity({g, 0, 0});
  const double mass = 2.5e6 * 4.0 / 3.0 * pi * std::pow(radius, 3);
  for (int k = 0; k < 40000; ++k) {  // overdamped: it creeps to rest over ~1000 steps
    sim->advance(1);
    Triple v = sim->velocity(1), w = sim->spin(1);
    for (double& x : v) x *= c;
    for (double& x : w) x *= c;
    sim->set_velocity(1, v);
    sim->set_spin(1, w);
  }
  const double stretch = sim->position(1)[0] - 2 * radius;
  INFO("stretch / (m g / k_n A) = " << stretch / (mass * g / (k_normal * area)));
  CHECK(norm(sim->velocity(1)) < 1e-12);
  CHECK(stretch == Approx(mass * g / (k_normal * area)).epsilon(1e-9));
}

TEMPLATE_TEST_CASE_SIG("bond: a bond made between moving particles starts unloaded", "[bond]",
                       ((int D), D), 2, 3) {
  // Two spheres flying apart: bonded now, at the places they have now, the
  // first step's forces (taken there) find the bond at its rest length; the
  // velocity they had came before it.
  const double speed = 0.01;
  auto sim = bonded_pair<D>(2500, 1e-7, particle({0, 0, 0}, {-speed, 0.3 * speed, 0}),
                            particle({2 * radius, 0, 0}, {speed, 0, 0}, {0, 0, 5}), spec());
  sim->advance(1);
  const BondLoad<D>& first = sim->bonds().load[0];
  CHECK(first.normal == 0);
  CHECK(first.shear.norm() == 0);
  CHECK(Dim<D>::spin_sq(first.bending) == 0);
  // Made mid-run, after the pair moved: the same.
  Simulation<D> later;
  later.set_warning_handler([](const std::string&) {});
  later.add_material({"p", 2500, 0, 0, 0});
  later.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 1.0}});
  later.set_time_step(1e-7);
  later.add_particle(particle({0, 0, 0}, {-speed, 0, 0}));
  later.add_particle(particle({2 * radius, 0, 0}, {speed, 0, 0}));
  later.advance(10);
  REQUIRE(later.create_bonds(spec(1e15, 1e15, 1e-3)) == 1);
  later.advance(1);
  CHECK(later.bonds().load[0].normal == 0);
  // A step on: one step's stretch, 2 speed dt.
  later.advance(1);
  CHECK(-later.bonds().load[0].normal == Approx(k_normal * area * 2 * speed * 1e-7).epsilon(1e-6));
}

TEMPLATE_TEST_CASE_SIG(
    "bond: a checkpoint between a script's velocities and the next step resumes bit-identical",
    "[bond][checkpoint]", ((int D), D), 2, 3) {
  auto run = [](Simulation<D>& sim, bool save, StateBlob* saved) {
    for (int k = 0; k < 40; ++k) {
      sim.advance(1);
      Triple v = sim.velocity(1);
      for (double& x : v) x *= 0.5;
      sim.set_velocity(1, v);
      if (save && k == 19) *saved = sim.save_state();
    }
  };
  ParticleSpec top = particle({0, 0, 0});
  top.fixed = true;
  auto whole =
      bonded_pair<D>(2.5e6, 2e-6, top, particle({2 * radius, 0, 0}, {1e-3, 2e-3, 0}), spec());
  StateBlob saved;
  run(*whole, true, &saved);
  REQUIRE(saved.integers.count("bonds.moved_with.ids"));
  auto resumed = bonded_pair<D>(2.5e6, 2e-6, top, particle({2 * radius, 0, 0}), spec());
  resumed->load_state(saved);
  for (int k = 20; k < 40; ++k) {
    resumed->advance(1);
    Triple v = resumed->velocity(1);
    for (double& x : v) x *= 0.5;
    resumed->set_velocity(1, v);
  }
  CHECK(whole->bonds().load[0].normal == resumed->bonds().load[0].normal);
  CHECK(whole->bonds().load[0].shear == resumed->bonds().load[0].shear);
  CHECK(whole->flat_state().position == resumed->flat_state().position);
  // A damaged entry is refused by name.
  StateBlob bad = saved;
  bad.doubles.at("bonds.moved_with").pop_back();
  auto target = bonded_pair<D>(2.5e6, 2e-6, top, particle({2 * radius, 0, 0}), spec());
  CHECK_THROWS_WITH(target->load_state(bad), Catch::Contains("'bonds.moved_with'"));
}

TEST_CASE("bond: a particle's bonds are found however they were made, moved, removed, restored",
          "[bond]") {
  // A removal breaks exactly the removed particle's bonds: those made before a
  // move looked them up, those made after (the engine's index of bonds by
  // particle must follow), and after a restart.
  auto scene = [](Simulation<3>& sim) {
    sim.set_warning_handler([](const std::string&) {});
    sim.add_material({"p", 2500, 0, 0, 0});
    sim.set_contact("p", "p", "linear", {{"k_normal", 1e3}, {"restitution", 1.0}});
    sim.set_time_step(1e-7);
  };
  Simulation<3> sim;
  scene(sim);
  for (int k = 0; k < 3; ++k) sim.add_particle(particle({2 * radius * k, 0, 0}));
  REQUIRE(sim.create_bonds(spec(1e15, 1e15, 1e-9)) == 2);  // 0-1, 1-2
  sim.set_position(0, {-1e-6, 0, 0});                      // looks up 0's bonds
  sim.advance(1);
  const std::int64_t fourth = sim.add_particle(particle({6 * radius, 0, 0}));
  REQUIRE(sim.create_bonds(spec(1e15, 1e15, 1e-9)) == 1);  // 2-3, made after the look-up
  sim.remove_particle(fourth);
  auto records = sim.bond_records();
  REQUIRE(records.size() == 3);
  CHECK_FALSE(records[0].broken);
  CHECK_FALSE(records[1].broken);
  CHECK(records[2].broken);
  CHECK(sim.bond_counts().intact == 2);

  Simulation<3> resumed;
  scene(resumed);
  resumed.load_state(sim.save_state());
  resumed.remove_particle(1);  // both of its bonds, in the restored scene
  records = resumed.bond_records();
  CHECK(records[0].broken);
  CHECK(records[1].broken);
  CHECK(resumed.bond_counts().intact == 0);
}
