// The contact log's list of active slots (ContactLog::slots), built after the
// force kernels on the steps that log contacts, from the lists of touching
// contacts the kernels made anyway. Observers then visit the few hundred
// contacts of a step instead of its thousands of candidate slots.
#include "engine/simulation.hpp"

namespace granule {

template <int D>
void Simulation<D>::list_logged_slots() {
  auto& slots = log_.slots;
  slots.clear();
  // Pair buckets first, then wall buckets, each in model order: slot order,
  // since the offsets were handed out in that order (rebuild_lists()).
  auto add = [&](const auto& bucket) {
    if (!bucket.size()) return;
    for (const auto& list : bucket.touched)
      for (const std::uint32_t entry : list)
        if (entry & 1) slots.push_back(static_cast<std::uint32_t>(bucket.offset + (entry >> 1)));
  };
  for_each_model([&](auto index) { add(std::get<decltype(index)::value>(pair_buckets_)); });
  for_each_model([&](auto index) { add(std::get<decltype(index)::value>(wall_buckets_)); });
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
