// What the property suite (test_model_properties.cpp) needs to run any
// registered contact model: its parameters (the descriptors' defaults plus one
// table of required values per model), a contact path that drives the law
// directly, and a two-particle scene that drives it through the engine.
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "contact/models.hpp"
#include "core/errors.hpp"
#include "engine/simulation.hpp"

namespace granule::test {

// The values the suite gives each registered model, by parameter name:
// `required` holds its descriptors' required parameters (and any other the
// suite needs set for the model to show its physics: thornton_jkr's
// surface_energy, which otherwise comes from the materials); `elastic` the
// changes that make its law elastic (no damping, no adhesion). All else is the
// descriptors' defaults; the friction coefficient is suite_friction.
struct SuiteParameters {
  ParamValues required;
  ParamValues elastic;
};

inline const std::map<std::string, SuiteParameters>& suite_parameters() {
  static const std::map<std::string, SuiteParameters> table = {
      {"linear", {{{"k_normal", 2e4}, {"restitution", 0.8}}, {{"restitution", 1.0}}}},
      {"walton_braun", {{{"k_load", 2e4}, {"restitution", 0.85}}, {{"restitution", 1.0}}}},
      {"hertz_mindlin", {{{"restitution", 0.8}}, {{"restitution", 1.0}}}},
      {"thornton_elastic", {{}, {}}},
      {"thornton_jkr", {{{"surface_energy", 0.05}}, {{"surface_energy", 0.0}}}},
  };
  return table;
}

constexpr double suite_friction = 0.3;
constexpr double suite_rolling_friction = 0.2;
constexpr double suite_twisting_friction = 0.1;  // 3D: a 2D scene refuses it

// The name of the model M is, or carries rolling resistance for.
template <typename M>
std::string rolling_base_name() {
  if constexpr (has_rolling<M>::value)
    return M::Base::name;
  else
    return M::name;
}
constexpr const char* suite_table_place =
    "suite_parameters() in tests/contact/model_properties.hpp";

// Glass-like spheres: E and nu for the laws that derive their stiffness from them.
inline Material suite_material(const std::string& name) {
  return {name, 2500, 70e9, 0.3, 0};
}

// The parameters the scene gives for model M (resolved by the engine) in a
// scene of `dimension`.
template <typename M>
ParamValues given_parameters(bool elastic, int dimension = 3) {
  const auto& table = suite_parameters();
  // A rolling variant (rolling.hpp) takes its model's values and a rolling friction.
  constexpr bool rolling = has_rolling<M>::value;
  const auto it = table.find(rolling_base_name<M>());
  if (it == table.end())
    FAIL("add the required parameters of " << M::name << " to " << suite_table_place);
  ParamValues given = it->second.required;
  if (elastic)
    for (const auto& [key, value] : it->second.elastic) given[key] = value;
  if (rolling) {
    given["rolling_friction"] = suite_rolling_friction;
    if (dimension == 3) given["twisting_friction"] = suite_twisting_friction;
    // Both forms of the term: the constant torque for the models Walton-Braun
    // and Thornton's elastic one, the EPSD spring for the others.
    const std::string base = rolling_base_name<M>();
    if (base == "walton_braun" || base == "thornton_elastic")
      given["rolling_model"] = rolling_model::constant;
  }
  bool has_friction = false;
  for (const auto& p : M::parameters()) has_friction |= std::string(p.name) == "friction";
  if (!has_friction)
    FAIL(M::name << " has no 'friction' parameter: the suite sets the friction coefficient "
                    "through it (say in "
                 << suite_table_place << " how this model's friction is given)");
  given["friction"] = suite_friction;
  return given;
}

// The same with the descriptors' defaults filled in.
template <typename M>
ParamValues resolved_parameters(bool elastic) {
  const ParamValues given = given_parameters<M>(elastic);
  try {
    return resolve_parameters(M::parameters(), given, M::name);
  } catch (const InputError& e) {
    FAIL("add the required parameters of " << M::name << " to " << suite_table_place << ": "
                                           << e.what());
  }
  return {};
}

template <typename M>
typename M::Params suite_params(bool elastic) {
  const Material m = suite_material("p");
  return M::make(resolved_parameters<M>(elastic), {m, m});
}

// The contact path of the law tests: two spheres of radius path_radius whose
// normal turns about a tilted axis (3D) or in the plane (2D), whose overlap
// loads, unloads and goes negative (the contact ends and forms again), and
// whose contact points slide back and forth along a direction that turns in
// the tangent plane. `rotation` turns the whole geometry.
constexpr double path_radius = 1e-4, path_depth = 1e-6, path_dt = 2e-9;
constexpr int path_steps = 20000;

template <int D>
ContactState<D> path_state(int k, const Eigen::Matrix<double, D, D>& rotation) {
  const double r_star = path_radius / 2;
  const double m_star = sphere_mass(path_radius, suite_material("p").density) / 2;
  const double turn = 0.3 * std::sin(1e-3 * k);
  const double overlap = path_depth * (0.6 + std::sin(2.3e-3 * k));
  const double normal_rate = path_depth * 2.3e-3 * std::cos(2.3e-3 * k) / path_dt;
  const double slip_speed = 0.5 * std::cos(1e-3 * k);
  Vec<D> n, t;
  if constexpr (D == 2) {
    n = Vec<2>(std::cos(turn), std::sin(turn));
    t = Vec<2>(-n.y(), n.x());
  } else {
    const Eigen::Matrix3d frame =
        Eigen::AngleAxisd(turn, Eigen::Vector3d(0.3, 0.5, 0.8).normalized()).toRotationMatrix();
    const double swing = 0.8 * std::sin(1.3e-3 * k);
    n = frame * Eigen::Vector3d::UnitX();
    t = frame * Eigen::Vector3d(0, std::cos(swing), std::sin(swing));
  }
  ContactState<D> c;
  c.normal = rotation * n;
  c.overlap = overlap;
  c.normal_velocity = normal_rate;
  c.tangential_velocity = rotation * (slip_speed * t);
  c.effective_mass = m_star;
  c.inv_mass_sum = 1 / m_star;
  c.effective_radius = r_star;
  c.dt = path_dt;
  return c;
}

// One step of a contact as the engine takes it: a pair that no longer
// touches (overlap <= 0, or beyond an adhesive model's reach) has its history
// cleared and no force.
template <typename M, int D>
ContactForce<D> engine_like_step(const typename M::Params& p, typename M::template History<D>& h,
                                 const ContactState<D>& c) {
  const bool touches = M::adhesive ? M::touching(p, h, c.overlap) : c.overlap > 0;
  if (!touches) {
    h = typename M::template History<D>{};
    return {};
  }
  return M::template force<D>(p, h, c);
}

// Two spheres (or one) through the real engine.
struct PairSetup {
  std::string model;
  ParamValues given;
  double radius_a = 1e-4, radius_b = 0.7e-4;
  Triple position_a{}, position_b{}, velocity_a{}, velocity_b{}, spin_a{}, spin_b{};
  double steps_per_contact = 40;
};

template <int D>
struct EnginePair {
  std::unique_ptr<Simulation<D>> sim = std::make_unique<Simulation<D>>();
  std::int64_t a = -1, b = -1;
  explicit EnginePair(const PairSetup& s) {
    sim->set_warning_handler([](const std::string&) {});
    sim->add_material(suite_material("p"));
    sim->set_contact("p", "p", s.model, s.given);
    sim->set_steps_per_contact(s.steps_per_contact);
    sim->set_record_contacts(true);
    ParticleSpec pa, pb;
    pa.radius = s.radius_a, pb.radius = s.radius_b;
    pa.material = pb.material = 0;
    pa.position = s.position_a, pb.position = s.position_b;
    pa.velocity = s.velocity_a, pb.velocity = s.velocity_b;
    pa.spin = s.spin_a, pb.spin = s.spin_b;
    // b first: its storage index comes before a's, and a re-sort along the
    // space-filling curve (a lies at lower x) swaps the two.
    b = sim->add_particle(pb);
    a = sim->add_particle(pa);
    sim->prepare();
  }
};

inline Eigen::Vector3d as_vec(const Triple& t) {
  return {t[0], t[1], t[2]};
}
inline Triple as_triple(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

// An oblique impact with spins: b (the smaller) at the origin, a arriving from
// -x with its centre line at 30 degrees to its velocity, both spinning; in 2D
// the same in the x-y plane.
template <int D>
PairSetup oblique_impact(const std::string& model, const ParamValues& given) {
  PairSetup s;
  s.model = model;
  s.given = given;
  const double d = (s.radius_a + s.radius_b) * (1 + 1e-3), angle = pi / 6;
  const Eigen::Vector3d line =
      D == 3 ? Eigen::Vector3d(-std::cos(angle), 0.6 * std::sin(angle), 0.8 * std::sin(angle))
             : Eigen::Vector3d(-std::cos(angle), std::sin(angle), 0);
  s.position_a = as_triple(d * line);
  s.velocity_a = {0.1, 0, 0};
  s.spin_a = D == 3 ? Triple{0, 300, -200} : Triple{0, 0, 300};
  s.spin_b = D == 3 ? Triple{100, 0, 150} : Triple{0, 0, -150};
  return s;
}

}  // namespace granule::test
