// A rank's share of a distributed scene (parallel/distributed_run.hpp): its
// owned particles' contact histories packed to travel with them, and a new
// share installed with the histories that arrived. The packing is per
// contact, keyed by particle ids and wall indices, so a contact two ranks both
// compute (a pair straddling their boxes) arrives twice as the same bytes, and
// either copy is the history.
#include <fmt/format.h>

#include <algorithm>
#include <tuple>
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

// A contact's track (hooks/contact_log.hpp: when it began, its peaks so far),
// which travels with its history while contact events are tracked: a contact
// going on across a migration, or across the end of one spread run and the start
// of the next, keeps its begin and its peaks as on one process.
template <typename Bucket>
auto track_of(const Bucket& b, std::size_t k) {
  using Track = typename std::decay_t<decltype(b.track)>::value_type;
  return b.track.size() == b.size() ? b.track[k] : Track{};
}

// Did the contact in `slot` touch at the last step? One that did not has a
// cleared history: nothing to carry. Before any step every slot counts.
template <typename Flags>
bool touched(const Flags& in_contact, std::size_t slot_count, std::size_t slot) {
  return in_contact.size() != slot_count || in_contact[slot] != 0;
}

}  // namespace

template <int D>
double Simulation<D>::interaction_reach() const {
  double r_max = 0;
  for (std::size_t k = 0; k < p_.size(); ++k) r_max = std::max(r_max, p_.radius[k]);
  return 2 * r_max + skin_ + contact_reach_;
}

// What reads the lists by storage index between steps needs them current.
template <int D>
void Simulation<D>::require_current_indices(const char* what) const {
  if (list_indices_stale_)
    throw RunError(
        fmt::format("distributed run: {} read lists whose storage indices a removal made stale "
                    "(renew_lists_if_indices_stale() first)",
                    what));
}

template <int D>
std::vector<std::string> Simulation<D>::pack_histories(
    const std::vector<std::uint8_t>* only) const {
  require_current_indices("pack_histories");
  std::vector<std::string> out(p_.size());
  auto wanted = [&](std::uint32_t q) { return !only || (*only)[q] != 0; };
  auto in_contact = [&](std::size_t slot) { return touched(slot_in_contact_, slot_count_, slot); };
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (!in_contact(b.offset + k)) continue;
      for (const std::uint32_t q : {b.i[k], b.j[k]}) {
        if ((p_.fixed[q] & ghost_flag) || !wanted(q)) continue;
        std::string& s = out[q];
        put(s, std::uint8_t{pair_entry});
        put(s, std::int32_t{I});
        put(s, b.id_i[k]);
        put(s, b.id_j[k]);
        put(s, b.history[k]);
        if (tracking_) put(s, track_of(b, k));
      }
    }
    const auto& w = std::get<I>(wall_buckets_);
    for (std::size_t k = 0; k < w.size(); ++k) {
      if (!in_contact(w.offset + k) || !wanted(w.particle[k])) continue;
      std::string& s = out[w.particle[k]];
      put(s, std::uint8_t{wall_entry});
      put(s, std::int32_t{I});
      put(s, w.id[k]);
      put(s, w.wall[k]);
      put(s, w.part[k]);
      put(s, w.history[k]);
      put(s, k < w.part_normal.size() ? w.part_normal[k] : Vec<D>(Vec<D>::Zero()));
      if (tracking_) put(s, track_of(w, k));
    }
  });
  return out;
}

template <int D>
std::vector<std::uint32_t> Simulation<D>::contacts_per_particle() const {
  require_current_indices("contacts_per_particle");
  std::vector<std::uint32_t> count(p_.size(), 0);
  if (slot_in_contact_.size() != slot_count_) return count;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k)
      if (slot_in_contact_[b.offset + k]) ++count[b.i[k]], ++count[b.j[k]];
    const auto& w = std::get<I>(wall_buckets_);
    for (std::size_t k = 0; k < w.size(); ++k)
      if (slot_in_contact_[w.offset + k]) ++count[w.particle[k]];
  });
  return count;
}

template <int D>
std::string Simulation<D>::pack_led_contacts() const {
  require_current_indices("pack_led_contacts");
  std::string out;
  if (!record_contacts_) return out;
  if (!log_.filled) return holds_share() ? out : pack_kept_contacts();
  auto put_record = [&](std::uint8_t kind, std::int32_t model, std::int64_t id_a, std::int64_t b,
                        std::uint8_t part, std::size_t s) {
    put(out, kind), put(out, model), put(out, id_a), put(out, b), put(out, part);
    put(out, log_.overlap[s]), put(out, log_.normal_force[s]);
    put(out, to_triple(log_.tangential[s])), put(out, to_triple(log_.normal[s]));
  };
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    for (std::size_t k = 0; k < b.size(); ++k) {
      const std::size_t s = b.offset + k;
      // Oriented id_i < id_j (contact_lists.hpp): i leads.
      if (!log_.active[s] || (p_.fixed[b.i[k]] & ghost_flag)) continue;
      put_record(pair_entry, I, b.id_i[k], b.id_j[k], 0, s);
    }
    const auto& w = std::get<I>(wall_buckets_);
    for (std::size_t k = 0; k < w.size(); ++k) {
      const std::size_t s = w.offset + k;
      if (log_.active[s]) put_record(wall_entry, I, w.id[k], w.wall[k], w.part[k], s);
    }
  });
  return out;
}

// The whole scene's contacts kept by id (a checkpoint's, or the log's made
// records before a removal) packed as pack_led_contacts packs the log's: the
// same records, in their (canonical) order, a contact's place among those of
// one particle with one wall standing for its part.
template <int D>
std::string Simulation<D>::pack_kept_contacts() const {
  std::string out;
  drop_removed_contacts();
  if (!gathered_contacts_) return out;
  std::vector<std::string> names;
  for_each_model(
      [&](auto index) { names.emplace_back(ContactModelAt<decltype(index)::value>::name); });
  const ContactRecord* previous = nullptr;
  std::uint8_t part = 0;
  for (const ContactRecord& c : *gathered_contacts_) {
    const auto model = std::find(names.begin(), names.end(), c.model) - names.begin();
    if (model == static_cast<std::ptrdiff_t>(names.size()))
      throw RunError(fmt::format("distributed run: a kept contact of model '{}'", c.model));
    const bool pair = c.id_b >= 0;
    const std::int64_t b = pair ? c.id_b : c.wall;
    const bool same_pair = previous && previous->model == c.model && previous->id_a == c.id_a &&
                           previous->id_b == c.id_b && previous->wall == c.wall;
    part = same_pair ? static_cast<std::uint8_t>(part + 1) : std::uint8_t{0};
    put(out, static_cast<std::uint8_t>(pair ? pair_entry : wall_entry));
    put(out, static_cast<std::int32_t>(model));
    put(out, c.id_a), put(out, b), put(out, part);
    put(out, c.overlap), put(out, c.normal_force), put(out, c.tangential_force), put(out, c.normal);
    previous = &c;
  }
  return out;
}

template <int D>
void Simulation<D>::set_gathered_contacts(const std::string& all) {
  struct Entry {
    std::uint8_t kind;
    std::int32_t model;
    std::int64_t b;  // the partner's id, or the wall
    std::uint8_t part;
    ContactRecord record;
  };
  std::vector<const char*> names;
  for_each_model(
      [&](auto index) { names.push_back(ContactModelAt<decltype(index)::value>::name); });
  std::vector<Entry> entries;
  for (std::size_t at = 0; at < all.size();) {
    Entry e;
    e.kind = take<std::uint8_t>(all, at);
    e.model = take<std::int32_t>(all, at);
    e.record.id_a = take<std::int64_t>(all, at);
    e.b = take<std::int64_t>(all, at);
    e.part = take<std::uint8_t>(all, at);
    if (e.model < 0 || static_cast<std::size_t>(e.model) >= names.size())
      throw RunError(fmt::format("distributed run: a gathered contact of model {}", e.model));
    ContactRecord& r = e.record;
    if (e.kind == wall_entry)
      r.wall = static_cast<int>(e.b);
    else
      r.id_b = e.b;
    r.model = names[static_cast<std::size_t>(e.model)];
    r.overlap = take<double>(all, at);
    r.normal_force = take<double>(all, at);
    r.tangential_force = take<Triple>(all, at);
    r.normal = take<Triple>(all, at);
    entries.push_back(std::move(e));
  }
  // The canonical slot order (Simulation::rebuild_lists): every model's pairs
  // by (id_i, id_j), then every model's wall contacts by (particle id, wall, part).
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::tie(x.kind, x.model, x.record.id_a, x.b, x.part) <
           std::tie(y.kind, y.model, y.record.id_a, y.b, y.part);
  });
  std::vector<ContactRecord> records;
  records.reserve(entries.size());
  for (Entry& e : entries) records.push_back(std::move(e.record));
  gathered_contacts_ = std::move(records);
  removed_from_gathered_.clear();
}

template <int D>
std::int64_t Simulation<D>::led_pair_contacts(std::int64_t* batched) const {
  std::int64_t led = 0, led_batched = 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(pair_buckets_);
    if (!b.size()) return;  // its kernel did not run: its lists are not this step's
    std::int64_t here = 0;
    // The last step's contacts are the entries of its lists with the touch
    // bit (buckets.hpp): far fewer than the candidates.
    for (const StepList<D>& list : b.touched)
      for (std::size_t e = 0; e < list.count; ++e) {
        const std::uint32_t entry = list.entries[e];
        if (!(entry & 1)) continue;  // stopped touching
        const std::uint32_t k = entry >> 1;
        // The pair is oriented id_i < id_j (buckets.hpp).
        const std::uint32_t lower = b.id_i[k] < b.id_j[k] ? b.i[k] : b.j[k];
        if (!(p_.fixed[lower] & ghost_flag)) ++here;
      }
    led += here;
    if (PairKernel<D, ContactModelAt<I>>::takes_batch(batched_contacts_)) led_batched += here;
  });
  if (batched) *batched = led_batched;
  return led;
}

template <int D>
void Simulation<D>::set_step_tallies(std::int64_t pair_contacts, std::int64_t pair_batched,
                                     std::int64_t wall_contacts, std::int64_t wall_batched,
                                     double max_overlap_ratio) {
  contacts_particle_ = pair_contacts;
  contacts_batched_ = pair_batched;
  contacts_wall_ = wall_contacts;
  contacts_wall_batched_ = wall_batched;
  max_overlap_ratio_ = max_overlap_ratio;
}

template <int D>
void Simulation<D>::set_wall_reactions(const std::vector<Vec<D>>& force,
                                       const std::vector<double>& axial_torque) {
  if (force.size() != walls_.size() || axial_torque.size() != walls_.size())
    throw RunError(fmt::format("distributed run: reactions for {} walls, the scene has {}",
                               force.size(), walls_.size()));
  for (std::size_t w = 0; w < walls_.size(); ++w)
    walls_[w].force = force[w], walls_[w].axial_torque = axial_torque[w];
}

template <int D>
std::string Simulation<D>::pack_wall_reactions() const {
  std::string out;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    const auto& b = std::get<I>(wall_buckets_);
    if (!b.size()) return;
    for (const auto& list : b.touched) {
      if (list.count > 0 && list.force.size() < list.count)
        throw RunError("distributed run: the walls' reactions were not kept (a fused step)");
      for (std::size_t e = 0; e < list.count; ++e) {
        const std::uint32_t k = list.entries[e] >> 1;
        put(out, std::int32_t{I});
        put(out, p_.id[b.particle[k]]);
        put(out, list.b[e]);
        put(out, list.force[e]);
        put(out, list.axial[e]);
      }
    }
  });
  return out;
}

template <int D>
void Simulation<D>::install_share(Particles<D> share, const std::vector<std::string>& histories,
                                  bool keep_own) {
  p_ = std::move(share);
  log_.filled = false;  // its entries name storage indices of the particles replaced
  gathered_contacts_.reset();
  removed_from_gathered_.clear();
  // The arrived histories become the "old" lists that rebuild_lists() carries
  // from, by id (contact_lists.hpp); the storage indices there are not read.
  // Kept ones first: the entries a packing would have given (those in contact
  // at the last step), moved instead of packed. A contact both kept and
  // arrived is the same bits on both sides, so whichever is found first will do.
  auto in_contact = [&](std::size_t slot) { return touched(slot_in_contact_, slot_count_, slot); };
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& b = std::get<I>(pair_buckets_);
    auto& w = std::get<I>(wall_buckets_);
    auto old_pairs = lists_detail::renew(b);
    auto old_walls = lists_detail::renew(w);
    if (!keep_own) return;
    for (std::size_t k = 0; k < old_pairs.size(); ++k) {
      if (!in_contact(old_pairs.offset + k)) continue;
      b.i.push_back(0), b.j.push_back(0), b.slot.push_back(0);
      b.id_i.push_back(old_pairs.id_i[k]), b.id_j.push_back(old_pairs.id_j[k]);
      b.history.push_back(old_pairs.history[k]);
      if (tracking_) b.track.push_back(track_of(old_pairs, k));
    }
    for (std::size_t k = 0; k < old_walls.size(); ++k) {
      if (!in_contact(old_walls.offset + k)) continue;
      w.particle.push_back(0), w.slot.push_back(0);
      w.id.push_back(old_walls.id[k]);
      w.wall.push_back(old_walls.wall[k]);
      w.part.push_back(old_walls.part[k]);
      w.history.push_back(old_walls.history[k]);
      w.part_normal.push_back(k < old_walls.part_normal.size() ? old_walls.part_normal[k]
                                                               : Vec<D>(Vec<D>::Zero()));
      if (tracking_) w.track.push_back(track_of(old_walls, k));
    }
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
          if (tracking_) b.track.push_back(take<ContactTrack<D>>(bytes, at));
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
          if (tracking_) w.track.push_back(take<ContactTrack<D>>(bytes, at));
        }
      });
    }
  }
  rebuild_lists();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
