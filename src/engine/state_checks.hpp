// A checkpoint is a file anyone can edit or damage, and load_state copies its
// arrays straight into the engine: an index out of range would be read far past
// an array's end, a NaN or a negative mass would only show steps later as a run
// that blew up. So every value load_state reads is checked first, before any of
// the scene's state is replaced, and refused with the entry's name.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "contact/rolling.hpp"
#include "core/state.hpp"

namespace granule {

// The history record sizes a checkpoint may hold for model M in D dimensions:
// this build's, and, for a model with the rolling term, that of builds before
// its twisting torque ({base, rolling}; read with no twist held). In 3D the
// twist adds 8 bytes that no alignment padding takes in, so the sizes tell
// them apart; in 2D they may coincide, where the twist is never read.
template <int D, typename M>
constexpr bool is_history_without_twisting(std::int64_t bytes) {
  if constexpr (has_rolling<M>::value) {
    using Old = typename M::template HistoryWithoutTwisting<D>;
    static_assert(D == 2 || sizeof(Old) != sizeof(typename M::template History<D>));
    return bytes == static_cast<std::int64_t>(sizeof(Old)) &&
           sizeof(Old) != sizeof(typename M::template History<D>);
  } else {
    return false;
  }
}
template <int D, typename M>
constexpr bool is_known_history_layout(std::int64_t bytes) {
  return bytes == static_cast<std::int64_t>(sizeof(typename M::template History<D>)) ||
         is_history_without_twisting<D, M>(bytes);
}

// Throws InputError "checkpoint: '<key>' <why>".
[[noreturn]] void refuse_entry(const std::string& key, const std::string& why);

// Every entry load_state reads, for a scene of `material_count` materials and
// `wall_count` walls: sizes, index tables, finite and positive values.
template <int D>
void check_state(const StateBlob& s, std::size_t material_count, std::size_t wall_count);

}  // namespace granule
