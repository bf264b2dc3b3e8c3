// Simulation<D>'s checkpoint entries beside the state itself (simulation_state.cpp):
// what the last step left for a script to read, and the escaped-particle rule that
// decides whether a state may be saved as a failed run's and loaded again.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "engine/simulation.hpp"

namespace granule {

// The last step's results that a script reads between runs: sim:stats()' tallies,
// the walls' reactions (sim:wall().force) and the recorded contacts (sim:contacts(),
// sim:contact_arrays(), an output's contacts). The next step computes them anew,
// but a restart from a checkpoint written between runs reads them before it, so
// they travel with the state.
template <int D>
void Simulation<D>::save_last_step(StateBlob& s) const {
  s.integers["last_step.tallies"] = {
      contacts_particle_,  contacts_batched_, contacts_wall_, contacts_wall_batched_,
      candidates_visited_, prunes_,           rebalances_};
  s.doubles["last_step.max_overlap_ratio"] = {max_overlap_ratio_};
  std::vector<double> reactions;
  for (const auto& w : walls_) {
    for (int a = 0; a < D; ++a) reactions.push_back(w.force[a]);
    reactions.push_back(w.axial_torque);
  }
  s.doubles["last_step.wall_reactions"] = reactions;
  // A rank's share between gathers names only its part of the scene: nothing to keep.
  if (!record_contacts_ || !(gathered_contacts_ || (log_.filled && !external_rebuilds_))) return;
  std::vector<std::int64_t> ids;
  std::vector<double> values;
  std::vector<std::string> models;
  for (const ContactRecord& c : contacts()) {
    auto m = std::find(models.begin(), models.end(), c.model);
    if (m == models.end()) m = models.insert(models.end(), c.model);
    ids.insert(ids.end(), {c.id_a, c.id_b, c.wall, m - models.begin()});
    values.insert(values.end(),
                  {c.overlap, c.normal_force, c.tangential_force[0], c.tangential_force[1],
                   c.tangential_force[2], c.normal[0], c.normal[1], c.normal[2]});
  }
  std::string names;
  for (const auto& m : models) names += m + "\n";
  s.integers["last_step.contacts"] = std::move(ids);
  s.doubles["last_step.contacts"] = std::move(values);
  s.texts["last_step.contact_models"] = names;
}

// Checked by check_state; absent (a checkpoint of an older build): zeros and no
// contacts, as before any step.
template <int D>
void Simulation<D>::load_last_step(const StateBlob& s) {
  const auto tallies = s.integers.find("last_step.tallies");
  const bool have = tallies != s.integers.end();
  contacts_particle_ = have ? tallies->second[0] : 0;
  contacts_batched_ = have ? tallies->second[1] : 0;
  contacts_wall_ = have ? tallies->second[2] : 0;
  contacts_wall_batched_ = have ? tallies->second[3] : 0;
  candidates_visited_ = have ? tallies->second[4] : 0;
  prunes_ = have ? tallies->second[5] : 0;
  rebalances_ = have ? tallies->second[6] : 0;
  const auto overlap = s.doubles.find("last_step.max_overlap_ratio");
  max_overlap_ratio_ = overlap != s.doubles.end() ? overlap->second[0] : 0;
  const auto reactions = s.doubles.find("last_step.wall_reactions");
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const double* r = reactions != s.doubles.end() ? &reactions->second[(D + 1) * w] : nullptr;
    for (int a = 0; a < D; ++a) walls_[w].force[a] = r ? r[a] : 0.0;
    walls_[w].axial_torque = r ? r[D] : 0.0;
  }
  // The log names storage indices of the particles replaced: the saved records
  // (by id) answer the queries until the next step logs anew.
  log_.filled = false;
  removed_from_gathered_.clear();
  gathered_contacts_.reset();
  const auto ids = s.integers.find("last_step.contacts");
  if (!record_contacts_ || ids == s.integers.end()) return;
  const auto& values = s.d("last_step.contacts");
  const auto models = s.lines("last_step.contact_models");
  std::vector<ContactRecord> records(ids->second.size() / 4);
  for (std::size_t k = 0; k < records.size(); ++k) {
    const std::int64_t* i = &ids->second[4 * k];
    const double* v = &values[8 * k];
    ContactRecord& c = records[k];
    c.id_a = i[0], c.id_b = i[1], c.wall = static_cast<int>(i[2]);
    c.model = models[static_cast<std::size_t>(i[3])];
    c.overlap = v[0], c.normal_force = v[1];
    c.tangential_force = {v[2], v[3], v[4]};
    c.normal = {v[5], v[6], v[7]};
  }
  gathered_contacts_ = std::move(records);
}

// The first free particle whose centre lies beyond a wall by more than its radius
// (escaped: check_escapes stops a run there), and that wall; -1, -1 for none.
template <int D>
std::pair<std::int64_t, std::int64_t> Simulation<D>::escaped_particle_and_wall() const {
  for (std::size_t i = 0; i < p_.size(); ++i)
    for (std::size_t w = 0; w < walls_.size(); ++w)
      if (!p_.fixed[i] && walls_[w].clearance(p_.position[i], p_.radius[i]) + 2 * p_.radius[i] < 0)
        return {static_cast<std::int64_t>(i), static_cast<std::int64_t>(w)};
  return {-1, -1};
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
