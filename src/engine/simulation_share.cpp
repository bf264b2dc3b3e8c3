// A rank's share of a distributed scene (parallel/distributed_run.hpp): its
// owned particles' contact histories packed to travel with them, and a new
// share installed with the histories that arrived. The packing is per
// contact, keyed by particle ids and wall indices, so a contact two ranks both
// compute (a pair straddling their boxes) arrives twice as the same bytes, and
// either copy is the history.
#include <type_traits>

#include "core/bytes.hpp"
#include "core/errors.hpp"
#include "engine/simulation.hpp"
#include "neighbor/contact_lists.hpp"

namespace granule {

namespace {

enum : std::uint8_t { pair_entry = 0, wall_entry = 1 };

using bytes::put;

template <typename T>
T take(const std::string& packed, std::size_t& at) {
  return bytes::take<T>(packed, at, "distributed run: a packed contact history");
}

}  // namespace

template <int D>
double Simulation<D>::interaction_reach() const {
  double r_max = 0;
  for (std::size_t k = 0; k < p_.size(); ++k) r_max = std::max(r_max, p_.radius[k]);
  return 2 * r_max + skin_ + contact_reach_;
}

template <int D>
std::vector<std::string> Simulation<D>::pack_histories() const {
  std::vector<std::string> out(p_.size());
  // A slot not in contact at the last
  // step has a cleared history: nothing to carry.
  const bool any_slots = slot_in_contact_.size() == slot_count_;
  auto in_contact = [&](std::size_t slot) { return !any_slots || slot_in_contact_[slot] != 0; };
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (!in_contact(b.offset + k)) continue;
      for (const std::uint32_t q : {b.i[k], b.j[k]}) {
        if (p_.fixed[q] & ghost_flag) continue;
        std::string& s = out[q];
        put(s, std::uint8_t{pair_entry});
        put(s, std::int32_t{I});
        put(s, b.id_i[k]);
        put(s, b.id_j[k]);
        put(s, b.history[k]);
      }
    }
    const auto& w = std::get<I>(wall_buckets_);
    for (std::size_t k = 0; k < w.size(); ++k) {
      if (!in_contact(w.offset + k)) continue;
      std::string& s = out[w.particle[k]];
      put(s, std::uint8_t{wall_entry});
      put(s, std::int32_t{I});
      put(s, w.id[k]);
      put(s, w.wall[k]);
      put(s, w.part[k]);
      put(s, w.history[k]);
      put(s, k < w.part_normal.size() ? w.part_normal[k] : Vec<D>(Vec<D>::Zero()));
    }
  });
  return out;
}

template <int D>
void Simulation<D>::install_share(Particles<D> share, const std::vector<std::string>& histories) {
  p_ = std::move(share);
  // The arrived histories become the "old" lists that rebuild_lists() carries
  // from, by id (contact_lists.hpp); the storage indices there are not read.
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    lists_detail::renew(std::get<I>(pair_buckets_));
    lists_detail::renew(std::get<I>(wall_buckets_));
  });
  for (const std::string& bytes : histories) {
    for (std::size_t at = 0; at < bytes.size();) {
      const auto kind = take<std::uint8_t>(bytes, at);
      const auto model = take<std::int32_t>(bytes, at);
      if (kind > wall_entry || model < 0 || model >= static_cast<std::int32_t>(contact_model_count))
        throw RunError(
            fmt::format("distributed run: a packed history of kind {} for model {}", kind, model));
      for_each_model([&](auto index) {
        constexpr int I = decltype(index)::value;
        if (I != model) return;
        if (kind == pair_entry) {
          auto& b = std::get<I>(pair_buckets_);
          using PH = typename std::decay_t<decltype(b)>::History;
          const auto a = take<std::int64_t>(bytes, at), c = take<std::int64_t>(bytes, at);
          if (a < 0 || c < 0 || a >= p_.next_id || c >= p_.next_id)
            throw RunError(fmt::format("distributed run: a history of pair ({}, {})", a, c));
          b.i.push_back(0), b.j.push_back(0), b.slot.push_back(0);
          b.id_i.push_back(a), b.id_j.push_back(c);
          b.history.push_back(take<PH>(bytes, at));
        } else {
          auto& w = std::get<I>(wall_buckets_);
          using WH = typename std::decay_t<decltype(w)>::History;
          const auto id = take<std::int64_t>(bytes, at);
          if (id < 0 || id >= p_.next_id)
            throw RunError(fmt::format("distributed run: a wall history of particle {}", id));
          w.particle.push_back(0), w.slot.push_back(0);
          w.id.push_back(id);
          w.wall.push_back(take<std::uint32_t>(bytes, at));
          w.part.push_back(take<std::uint8_t>(bytes, at));
          w.history.push_back(take<WH>(bytes, at));
          w.part_normal.push_back(take<Vec<D>>(bytes, at));
        }
      });
    }
  }
  rebuild_lists();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
