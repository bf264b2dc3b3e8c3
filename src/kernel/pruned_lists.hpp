// Pruned pair lists (SimulationBase::set_pruning). On a step that notes, the
// pair kernel's listing pass runs over all candidates and also notes, per
// thread, those in contact or within the prune distance of touching; until
// the next note it runs over those only. A candidate left out cannot touch:
// it was not in contact and its particles, each moving at most the prune
// travel since, cannot have closed the distance (a new contact needs overlap
// > 0, adhesive ones too: a contact that holds on at a gap was in contact when
// noted). The listing, hence every result, is the same as without pruning.
// The notes are per thread range, so they hold for one team's ranges.
#pragma once

#include <cstdint>
#include <vector>

#include "core/hot_array.hpp"

namespace granule {

class PrunedLists {
 public:
  // What the listing pass does this step.
  struct Plan {
    bool note = false;  // runs over all candidates and notes the near ones
    bool use = false;   // runs over the noted ones only
  };

  // `pruning`: on for this bucket this step; `due`: particles may have closed
  // the prune distance since the last global note; `split`: the team's ranges.
  Plan plan(bool pruning, bool due, int team, const std::vector<std::int64_t>& split) {
    if (!pruning) valid_ = false;  // notes not renewed at a global prune are stale
    Plan p;
    p.note = pruning &&
             (due || !valid_ || near_.size() != static_cast<std::size_t>(team) || split_ != split);
    p.use = pruning && !p.note && pays_;
    if (p.note) near_.resize(team);
    return p;
  }

  // Candidates the listing pass visits this step under `plan`, out of `count`.
  std::int64_t visited(const Plan& plan, std::int64_t count) const {
    if (!plan.use) return count;
    std::int64_t v = 0;
    for (const auto& near : near_) v += static_cast<std::int64_t>(near.size());
    return v;
  }

  // Thread t's noted candidates (written on a noting step, read on the others).
  HotArray<std::uint32_t>& of_thread(std::int64_t t) { return near_[t]; }

  // After a noting step run by `ran_team` threads of the `team` asked for,
  // over `count` candidates: notes taken by a smaller team are not per range.
  void noted(int team, int ran_team, const std::vector<std::int64_t>& split, std::int64_t count) {
    valid_ = ran_team == team;
    split_ = split;
    std::size_t noted = 0;
    for (const auto& near : near_) noted += near.size();
    // The noted pass reads one index more per candidate: worth it below ~80 %.
    pays_ = 5 * noted <= 4 * static_cast<std::size_t>(count);
  }

  // A new candidate list: nothing noted.
  void on_new_list() {
    near_.clear(), split_.clear();
    valid_ = pays_ = false;
  }

 private:
  // One per thread of the team that noted them, the candidates of its range
  // that were in contact or within the prune distance of touching when noted,
  // in increasing k.
  std::vector<HotArray<std::uint32_t>> near_;
  std::vector<std::int64_t> split_;  // the ranges they were noted for
  bool valid_ = false;  // false: note afresh (a new list, a step without pruning, a smaller team)
  bool pays_ = false;   // short enough to repay the extra index per candidate
};

}  // namespace granule
