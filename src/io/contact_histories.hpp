// Contact histories of a set of particles, cut from one simulation's state and
// put into another's. A prepared agglomerate (dissertation 7.3) is held
// together by its contacts' tangential forces and JKR contact radii (6.3); a
// snapshot keeps positions and velocities only, so without these a reloaded
// agglomerate starts with every tangential force at zero and rings.
//
// Both functions work on the arrays of a checkpoint (core/state.hpp, filled by
// Simulation::save_state): the pair lists "pairs.<model>.{i, j, slot, id_i,
// id_j, history, track, layout}" keyed by the particles' ids. The engine's own
// list rebuild then carries each history to its pair by id (rebuild_lists), as
// it does every time the lists are rebuilt.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/state.hpp"

namespace granule::io {

// The pair-list entries of `state` whose two particles are both in `ids`, each
// list under its model's keys (id_i, id_j, history, layout), with "meta" = {the
// state's dimension, its step}. What a file keeps (add_state_group).
StateBlob pair_histories_of(const StateBlob& state, const std::vector<std::int64_t>& ids);

// Puts the histories of `saved` (from pair_histories_of) into the pair lists of
// `state`, renaming each particle by `renamed` (saved id -> id in `state`): an
// existing entry for the pair takes the history, a missing one is added. The
// lists are marked for a rebuild, which keeps every history whose pair is still
// a candidate. Returns the number of histories put in. Throws InputError, naming
// `file`, for another dimension, a history layout this build does not have, an
// id that `renamed` lacks, or a renaming that reverses a pair's order (a history
// holds the force on the lower id: its sign would flip).
std::size_t seed_pair_histories(StateBlob& state, const StateBlob& saved,
                                const std::map<std::int64_t, std::int64_t>& renamed,
                                const std::string& file);

}  // namespace granule::io
