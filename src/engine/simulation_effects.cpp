// What a scene simulates (ActiveEffects): the material pairs that can meet,
// and from them whether adhesion and rotation are in play; fields, moving
// walls, diagnostics. The run header and /scene/effects report it, and
// prepare() takes from it what the step may skip (spins when nothing has
// friction, the adhesive reach of pairs that never meet).
#include <fmt/format.h>

#include <algorithm>

#include "engine/simulation.hpp"

namespace granule {

template <int D>
std::vector<std::pair<int, int>> Simulation<D>::pairs_in_use() const {
  const int nm = static_cast<int>(materials_.size());
  std::vector<char> particle(nm, 0), any(nm, 0);
  for (int m : p_.material) particle[m] = any[m] = 1;
  for (const auto& w : walls_) any[w.material] = 1;
  std::vector<std::pair<int, int>> out;
  for (int a = 0; a < nm; ++a)
    for (int b = a; b < nm; ++b)
      if ((particle[a] && any[b]) || (particle[b] && any[a])) out.emplace_back(a, b);
  return out;
}

template <int D>
ActiveEffects Simulation<D>::effects() const {
  ActiveEffects e;
  e.dimension = D;
  e.periodic = periodic_.on();
  const auto catalogue = contact_model_catalogue();
  const auto in_use = pairs_in_use();  // one pass over the particles
  // Adhesive laws at a surface energy of 0, which a schedule may raise: (a, b), label.
  std::vector<std::pair<std::pair<int, int>, std::string>> unstuck;
  for (auto [a, b] : in_use) {
    const PairTable::Entry& entry = pairs_.at(a, b);
    if (entry.model < 0) continue;  // prepare() refuses the scene if such a pair can occur
    const std::string label = fmt::format("{}-{} {}", materials_[a].name, materials_[b].name,
                                          catalogue[entry.model].name);
    e.pairs.push_back(label);
    bool adhesive = false;
    for_each_model([&](auto index) {
      constexpr int I = decltype(index)::value;
      if (entry.model == I) adhesive = ContactModelAt<I>::adhesive;
    });
    // An adhesive law at a surface energy of 0 sticks nothing (JKR reduces to
    // Hertz), unless a schedule raises it (below).
    if (adhesive) {
      const ParamValues acting = pairs_.values_in_effect(a, b, materials_);
      const auto gamma = acting.find("surface_energy");
      if (gamma == acting.end() || gamma->second != 0)
        e.adhesive_pairs.push_back(label);
      else
        unstuck.push_back({{a, b}, label});
    }
    // Every model caps the tangential force at mu times a normal force
    // (Eqs. 3.5, 6.8-6.10, 6.23-6.25): with mu = 0 no torque can act, but
    // for an adhesive pair's peeling (Eqs. 6.18-6.21), whose T rises to Tc
    // whatever mu (e.rotation below).
    const ParamValues& values = pairs_.values(a, b);
    auto mu = values.find("friction");
    if (mu == values.end() || mu->second != 0) e.friction = true;
    // A rolling torque turns the particles even without friction, as a bond's moments do.
    e.rolling |= entry.model >= base_contact_model_count;
  }
  e.bonds = bonds_.intact > 0;
  e.gravity = body_.gravity_on;
  e.central_field = body_.central_on && body_.central_strength != 0;
  e.damping = damping_.active();
  for (const auto& w : walls_)
    if (!w.velocity.isZero() || w.angular_velocity != 0) e.moving_walls.push_back(w.name);
  // What a schedule will set is simulated too: a friction ramp from 0, a wall
  // set moving, a field switched on (any value it passes through that is not 0).
  for (const auto& s : schedules_) {
    const auto& values = s.schedule.values();
    if (std::all_of(values.begin(), values.end(), [](double v) { return v == 0; })) continue;
    if (s.target == "central_strength") {
      e.central_field = true;
    } else if (s.wall >= 0) {
      const std::string& name = walls_[static_cast<std::size_t>(s.wall)].name;
      if (std::find(e.moving_walls.begin(), e.moving_walls.end(), name) == e.moving_walls.end())
        e.moving_walls.push_back(name);
    } else if (s.target == "friction") {
      const int a = material_id(s.a), b = material_id(s.b);
      const std::pair<int, int> pair{std::min(a, b), std::max(a, b)};
      e.friction |= std::find(in_use.begin(), in_use.end(), pair) != in_use.end();
    } else if (s.target == "surface_energy") {
      const int a = material_id(s.a), b = material_id(s.b);
      const std::pair<int, int> pair{std::min(a, b), std::max(a, b)};
      for (const auto& [law_pair, label] : unstuck)
        if (law_pair == pair) e.adhesive_pairs.push_back(label);
    }
  }
  e.adhesion = !e.adhesive_pairs.empty();
  // Spin damping slows the spins a scene set, whatever acts on them.
  e.rotation = e.friction || e.rolling || e.bonds || e.adhesion || damping_.spin > 0;
  for (const auto& d : diagnostics_) e.diagnostics.push_back(d.name);
  e.contacts_recorded = record_contacts_;
  e.canonical_order = canonical_order_;
  e.hooks = static_cast<int>(hooks_.size());
  e.threads = thread_count();
  e.ranks = spread_ranks_;
  e.decomposition = spread_how_;
  return e;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
