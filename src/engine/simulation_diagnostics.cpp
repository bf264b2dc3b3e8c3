// Simulation<D>::save_diagnostics / load_diagnostics: the attached
// diagnostics' accumulators in a checkpoint (core/state.hpp), so that a
// restarted run reports what the uninterrupted one reports. Beside them, the
// per-contact tracking (ContactTrack: when each contact began, its peaks so
// far) that the began/ended events come from: a contact going on across the
// checkpoint must end once, with its whole peak, and not begin again.
//
// Keys: "diagnostics.count", "diagnostics.names" (one per line, attach
// order), each diagnostic's entries under "diagnostics.<k>.", the tracking
// under "diagnostics.track.<pairs|walls>.<model>".
#include <fmt/format.h>

#include <cstring>
#include <sstream>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

namespace granule {

namespace {
constexpr const char* count_key = "diagnostics.count";
constexpr const char* names_key = "diagnostics.names";

std::string prefix_of(std::size_t k) {
  return fmt::format("diagnostics.{}.", k);
}

bool has_diagnostics(const StateBlob& s) {
  auto any = [](const auto& map) {
    auto it = map.lower_bound("diagnostics.");
    return it != map.end() && it->first.compare(0, 12, "diagnostics.") == 0;
  };
  return any(s.doubles) || any(s.integers) || any(s.bytes) || any(s.texts);
}

std::string listed(const std::vector<std::string>& names) {
  return names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "));
}

template <int D>
std::vector<std::uint8_t> track_bytes(const std::vector<ContactTrack<D>>& track) {
  // ContactTrack is doubles and a fixed-size Eigen vector: plain memory, copied exactly.
  std::vector<std::uint8_t> out(track.size() * sizeof(ContactTrack<D>));
  if (!track.empty()) std::memcpy(out.data(), track.data(), out.size());
  return out;
}
}  // namespace

template <int D>
void Simulation<D>::save_diagnostics(StateBlob& s) const {
  std::string names;
  for (const auto& d : diagnostics_) names += d.name + "\n";
  s.integers[count_key] = {static_cast<std::int64_t>(diagnostics_.size())};
  s.texts[names_key] = names;
  for (std::size_t k = 0; k < diagnostics_.size(); ++k)
    diagnostics_[k].diagnostic->save_state(s, prefix_of(k));
  s.integers["diagnostics.track.layout"] = {static_cast<std::int64_t>(sizeof(ContactTrack<D>)),
                                            tracking_ ? 1 : 0, ongoing_marks_due_ ? 1 : 0};
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    s.bytes[fmt::format("diagnostics.track.pairs.{}", M::name)] =
        track_bytes<D>(std::get<I>(pair_buckets_).track);
    s.bytes[fmt::format("diagnostics.track.walls.{}", M::name)] =
        track_bytes<D>(std::get<I>(wall_buckets_).track);
  });
}

template <int D>
void Simulation<D>::load_diagnostics(const StateBlob& s) {
  std::vector<std::string> attached;
  for (const auto& d : diagnostics_) attached.push_back(d.name);
  if (!has_diagnostics(s)) {
    if (diagnostics_.empty()) return;
    throw InputError(fmt::format(
        "checkpoint holds no diagnostics' state (written by an older build), but the scene "
        "attaches {}: their windows and sums would start again from nothing; continue from a "
        "newer checkpoint or start the run afresh",
        listed(attached)));
  }
  const auto& count = s.i(count_key);
  std::vector<std::string> saved;
  {
    std::istringstream in(s.t(names_key));
    for (std::string line; std::getline(in, line);) saved.push_back(line);
  }
  if (count.size() != 1 || count[0] != static_cast<std::int64_t>(saved.size()))
    throw InputError(fmt::format("checkpoint: '{}' does not match the {} names in '{}'", count_key,
                                 saved.size(), names_key));
  if (saved != attached)
    throw InputError(
        fmt::format("checkpoint's diagnostics ({}) differ from the scene's ({}): attach the same "
                    "diagnostics, in the same order, as the run that wrote it",
                    listed(saved), listed(attached)));

  // The tracking first: it needs the contact lists load_state() restored.
  const auto& layout = s.i("diagnostics.track.layout");
  if (layout.size() != 3 || layout[0] != static_cast<std::int64_t>(sizeof(ContactTrack<D>)) ||
      (layout[2] != 0 && layout[2] != 1))
    throw InputError(
        "checkpoint: 'diagnostics.track.layout' differs from this build's contact tracking "
        "(written by another build?)");
  // Whether the contacts going on were still to be marked (a checkpoint between an
  // attach and the next step): the tracks below are then not yet the run's.
  ongoing_marks_due_ = tracking_ && layout[2] != 0;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    auto restore = [&](auto& bucket, const char* kind) {
      bucket.track.clear();
      if (!tracking_) return;
      const std::string key = fmt::format("diagnostics.track.{}.{}", kind, M::name);
      const auto& bytes = s.b(key);
      // Saved without tracking (nothing attached needed events then): every
      // contact starts untracked, as the uninterrupted run's next step would.
      if (bytes.empty()) return;
      if (bytes.size() != bucket.size() * sizeof(ContactTrack<D>))
        throw InputError(fmt::format(
            "checkpoint: '{}' tracks {} contacts, the {} {} list holds {} (load the particles' "
            "state, load_state(), before the diagnostics')",
            key, bytes.size() / sizeof(ContactTrack<D>), M::name, kind, bucket.size()));
      bucket.track.resize(bucket.size());
      std::memcpy(static_cast<void*>(bucket.track.data()), bytes.data(), bytes.size());
    };
    restore(std::get<I>(pair_buckets_), "pairs");
    restore(std::get<I>(wall_buckets_), "walls");
  });
  for (std::size_t k = 0; k < diagnostics_.size(); ++k)
    diagnostics_[k].diagnostic->load_state(s, prefix_of(k));
}

template <int D>
bool Simulation<D>::whole_step_due() const {
  if (tracking_) return true;
  for (const auto& d : diagnostics_) {
    if (d.needs.events) return true;
    // As step() decides (its observe() and the samplings' own check): the
    // step count before the step, the time at its start.
    if (step_ % d.every == 0 && d.diagnostic->sampling().due(time_, dt_)) return true;
  }
  return false;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
