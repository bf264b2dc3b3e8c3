// A checkpoint is a file anyone can edit or damage, and load_state copies its
// arrays straight into the engine: an index out of range would be read far past
// an array's end, a NaN or a negative mass would only show steps later as a run
// that blew up. So every value load_state reads is checked first, before any of
// the scene's state is replaced, and refused with the entry's name.
#pragma once

#include <cstddef>
#include <string>

#include "core/state.hpp"

namespace granule {

// Throws InputError "checkpoint: '<key>' <why>".
[[noreturn]] void refuse_entry(const std::string& key, const std::string& why);

// Every entry load_state reads, for a scene of `material_count` materials and
// `wall_count` walls: sizes, index tables, finite and positive values.
template <int D>
void check_state(const StateBlob& s, std::size_t material_count, std::size_t wall_count);

}  // namespace granule
