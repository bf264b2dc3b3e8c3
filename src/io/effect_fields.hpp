// The fields of ActiveEffects that /scene/effects holds, by attribute name: one
// list for writing them (run_output_header.cpp) and for the checkpoint's copy
// of them (run_output_mark.cpp).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "engine/simulation_base.hpp"

namespace granule::io {

// The flags of ActiveEffects that /scene/effects holds, by name.
inline std::vector<std::pair<const char*, bool ActiveEffects::*>> effect_flags() {
  return {{"periodic", &ActiveEffects::periodic},
          {"adhesion", &ActiveEffects::adhesion},
          {"friction", &ActiveEffects::friction},
          {"rolling", &ActiveEffects::rolling},
          {"bonds", &ActiveEffects::bonds},
          {"rotation", &ActiveEffects::rotation},
          {"gravity", &ActiveEffects::gravity},
          {"central_field", &ActiveEffects::central_field},
          {"damping", &ActiveEffects::damping},
          {"contacts_recorded", &ActiveEffects::contacts_recorded},
          {"canonical_order", &ActiveEffects::canonical_order}};
}
inline std::vector<std::pair<const char*, std::vector<std::string> ActiveEffects::*>>
effect_lists() {
  return {{"pairs", &ActiveEffects::pairs},
          {"adhesive_pairs", &ActiveEffects::adhesive_pairs},
          {"moving_wall_names", &ActiveEffects::moving_walls},
          {"diagnostics", &ActiveEffects::diagnostics}};
}

}  // namespace granule::io
