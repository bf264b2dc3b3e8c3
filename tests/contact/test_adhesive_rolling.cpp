// Rolling and twisting resistance of adhesive contacts (thornton_jkr with the
// rolling term, contact/rolling.hpp and ThorntonJkr::resisting) against closed
// forms, through the engine.
//
// A JKR contact at rest carries no load (N = 0 at the contact radius a0 of
// Eq. 6.14) yet holds together, with the pull-off force Nc = 1.5 pi Gamma R*
// (Eq. 6.17). Its rolling and twisting caps take the load N + 2Nc, as the
// tangential law's slip does after peeling (Eq. 6.25), so at rest they are
// mu_r R* 2Nc and mu_t R* 2Nc; the epsd springs take k_n = 4 E* a / 3.
//
// Two equal spheres at rest in contact, spinning at +w0 and -w0 about an axis
// normal to the line of centres, roll on each other without slip (the levers
// are equal, so the surfaces at the contact move together): the rolling torque
// alone slows each, I dw/dt = -M, so the constant torque stops both at
// t = w0 I / (mu_r R* 2Nc); below the cap the epsd spring makes the relative
// rotation ring at omega^2 = 2 k_r / I, k_r = 2.25 k_n (mu_r R*)^2.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "contact/rolling.hpp"
#include "contact/thornton_jkr.hpp"
#include "engine/simulation.hpp"

using namespace granule;

namespace {

constexpr double radius = 1e-4, density = 1000, young = 1e8, poisson = 0.3, surface_energy = 0.1;

// E* of two bodies of the material above (1/E* = 2 (1 - nu^2) / E).
constexpr double e_star = young / (2 * (1 - poisson * poisson));

// The overlap at which a JKR contact of effective radius r_star carries no load.
double rest_overlap(double r_star) {
  const double a0 = ThorntonJkr::zero_load_radius(surface_energy, r_star, e_star);
  return a0 * a0 / r_star - std::sqrt(2 * pi * surface_energy * a0 / e_star);  // Eq. 6.14
}

template <int D>
std::unique_ptr<Simulation<D>> jkr_scene(const ParamValues& rolling) {
  auto sim = std::make_unique<Simulation<D>>();
  sim->set_warning_handler([](const std::string&) {});
  sim->add_material({"p", density, young, poisson, 0});
  sim->add_material({"w", 0, young, poisson, 0});
  ParamValues law{{"friction", 0.3}, {"surface_energy", surface_energy}};
  for (const auto& [k, v] : rolling) law[k] = v;
  sim->set_contact("p", "p", "thornton_jkr", law);
  sim->set_contact("p", "w", "thornton_jkr", law);
  return sim;
}

struct Pair {
  std::unique_ptr<SimulationBase> sim;
  std::int64_t a = 0, b = 0;
};

// Two spheres at rest at the no-load overlap along x, spinning at +w0 and -w0 about z.
template <int D>
Pair counter_spinning(const ParamValues& rolling, double w0) {
  Pair p;
  auto sim = jkr_scene<D>(rolling);
  const double half_gap = radius - 0.5 * rest_overlap(0.5 * radius);
  ParticleSpec s;
  s.radius = radius;
  s.material = 0;
  s.position = {-half_gap, 0, 0};
  s.spin = {0, 0, w0};
  p.a = sim->add_particle(s);
  s.position = {half_gap, 0, 0};
  s.spin = {0, 0, -w0};
  p.b = sim->add_particle(s);
  sim->prepare();
  p.sim = std::move(sim);
  return p;
}

const double mass = sphere_mass(radius, density);
const double inertia = sphere_inertia(mass, radius);

// Steps until sphere a's spin first reaches zero, or max_steps: the time it did.
double first_stop(SimulationBase& sim, std::int64_t id, int axis, double w0, double max_time) {
  const double dt = sim.time_step();
  for (std::int64_t k = 0; k * dt < max_time; ++k) {
    sim.advance(1);
    if (sim.spin(id)[axis] <= 1e-12 * w0) return sim.time();
  }
  return -1;
}

}  // namespace

TEMPLATE_TEST_CASE_SIG(
    "adhesive rolling: a JKR pair at rest stops rolling at t = w0 I / (mu_r R* 2Nc)",
    "[rolling][adhesive]", ((int D), D), 2, 3) {
  const double w0 = 5000, mu_r = 0.1, r_star = 0.5 * radius;
  Pair p = counter_spinning<D>(
      {{"rolling_friction", mu_r}, {"rolling_model", rolling_model::constant}}, w0);
  const double nc = ThorntonJkr::pull_off_force(surface_energy, r_star);
  const double expected = w0 * inertia / (mu_r * r_star * 2 * nc);
  const double dt = p.sim->time_step();
  const double stopped = first_stop(*p.sim, p.a, 2, w0, 2 * expected);
  INFO(D << "D: stopped at " << stopped << " s, closed form " << expected << " s (" << expected / dt
         << " steps)");
  CHECK(expected / dt > 300);  // resolved
  CHECK(std::abs(stopped - expected) <= 2 * dt + 2e-3 * expected);
  // Both stop together and stay stopped; the centres did not move (no slip).
  p.sim->advance(static_cast<std::int64_t>(0.2 * expected / dt));
  CHECK(std::abs(p.sim->spin(p.a)[2]) <= 1e-9 * w0);
  CHECK(std::abs(p.sim->spin(p.b)[2]) <= 1e-9 * w0);
  const Triple xa = p.sim->position(p.a);
  CHECK(std::abs(xa[1]) <= 1e-6 * radius);
}

TEMPLATE_TEST_CASE_SIG(
    "adhesive rolling: the epsd spring of a JKR pair at rest rings at "
    "omega^2 = 2 k_r / I with k_n = 4 E* a0 / 3",
    "[rolling][adhesive]", ((int D), D), 2, 3) {
  const double mu_r = 0.1, r_star = 0.5 * radius;
  const double a0 = ThorntonJkr::zero_load_radius(surface_energy, r_star, e_star);
  const double k_r = 2.25 * (4.0 / 3.0 * e_star * a0) * (mu_r * r_star) * (mu_r * r_star);
  const double omega = std::sqrt(2 * k_r / inertia);
  // Swinging to a third of the angle at which the spring slips (cap / k_r).
  const double slip_angle =
      mu_r * r_star * 2 * ThorntonJkr::pull_off_force(surface_energy, r_star) / k_r;
  const double w0 = 0.5 * (slip_angle / 3) * omega;  // relative amplitude 2 w0 / omega
  Pair p = counter_spinning<D>({{"rolling_friction", mu_r}}, w0);
  const double dt = p.sim->time_step();
  const double period = 2 * pi / omega;
  // Zero crossings of sphere a's spin, interpolated within the step.
  std::vector<double> crossings;
  double before = w0;
  for (std::int64_t k = 0; k * dt < 2.2 * period && crossings.size() < 4; ++k) {
    p.sim->advance(1);
    const double now = p.sim->spin(p.a)[2];
    if ((before > 0) != (now > 0)) crossings.push_back(p.sim->time() - dt * now / (now - before));
    before = now;
  }
  REQUIRE(crossings.size() >= 3);
  const double measured = crossings[2] - crossings[0];
  INFO(D << "D: period " << measured << " s, closed form " << period << " s (" << period / dt
         << " steps); the spring slips at " << slip_angle << " rad");
  CHECK(std::abs(measured - period) <= 5e-3 * period);
}

TEST_CASE(
    "adhesive twisting: a JKR sphere at rest on a wall stops twisting at "
    "t = w0 I / (mu_t r 2Nc)",
    "[twisting][adhesive]") {
  const double w0 = 20000, mu_t = 0.1;  // the wall's R* = r: twice the pair's cap
  auto sim =
      jkr_scene<3>({{"twisting_friction", mu_t}, {"rolling_model", rolling_model::constant}});
  WallSpec w;
  w.name = "floor";
  w.material = 1;
  w.normal = {0, 1, 0};
  sim->add_wall(w);
  ParticleSpec s;
  s.radius = radius;
  s.material = 0;
  s.position = {0, radius - rest_overlap(radius), 0};  // R* = r on a plane
  s.spin = {0, w0, 0};
  const std::int64_t id = sim->add_particle(s);
  sim->prepare();
  const double nc = ThorntonJkr::pull_off_force(surface_energy, radius);
  const double expected = w0 * inertia / (mu_t * radius * 2 * nc);
  const double dt = sim->time_step();
  const double stopped = first_stop(*sim, id, 1, w0, 2 * expected);
  INFO("stopped at " << stopped << " s, closed form " << expected << " s (" << expected / dt
                     << " steps)");
  CHECK(expected / dt > 300);
  CHECK(std::abs(stopped - expected) <= 2 * dt + 2e-3 * expected);
  // Still held on the wall at its no-load overlap: N stayed ~0 while it spun down.
  CHECK(std::abs(sim->position(id)[1] - s.position[1]) <= 1e-3 * rest_overlap(radius));
}
