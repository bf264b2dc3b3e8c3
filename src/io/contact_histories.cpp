#include "io/contact_histories.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "core/errors.hpp"

namespace granule::io {

namespace {

// "pairs.<model>." for every pair list of a state.
std::vector<std::string> pair_prefixes(const StateBlob& s) {
  std::vector<std::string> out;
  const std::string head = "pairs.", tail = ".id_i";
  for (const auto& entry : s.integers) {
    const std::string& k = entry.first;
    if (k.size() > head.size() + tail.size() && k.compare(0, head.size(), head) == 0 &&
        k.compare(k.size() - tail.size(), tail.size(), tail) == 0)
      out.push_back(k.substr(0, k.size() - tail.size() + 1));
  }
  return out;
}

std::string model_of(const std::string& prefix) {
  return prefix.substr(6, prefix.size() - 7);  // between "pairs." and the final '.'
}

}  // namespace

StateBlob pair_histories_of(const StateBlob& state, const std::vector<std::int64_t>& ids) {
  const std::unordered_set<std::int64_t> in(ids.begin(), ids.end());
  StateBlob out;
  const auto& meta = state.i("meta");
  out.integers["meta"] = {meta.at(1), meta.at(2)};
  // What the rolling springs hold (Simulation::save_state): absent in files of older builds.
  if (state.integers.count("rolling_springs"))
    out.integers["rolling_springs"] = state.i("rolling_springs");
  for (const std::string& pk : pair_prefixes(state)) {
    const auto& id_i = state.i(pk + "id_i");
    const auto& id_j = state.i(pk + "id_j");
    const auto& history = state.b(pk + "history");
    const std::int64_t size = state.i(pk + "layout").at(1);
    std::vector<std::int64_t> a, b;
    std::vector<std::uint8_t> h;
    for (std::size_t k = 0; k < id_i.size(); ++k) {
      if (!in.count(id_i[k]) || !in.count(id_j[k])) continue;
      a.push_back(id_i[k]);
      b.push_back(id_j[k]);
      const auto first = history.begin() + static_cast<std::ptrdiff_t>(k * size);
      h.insert(h.end(), first, first + size);
    }
    if (a.empty()) continue;
    out.integers[pk + "id_i"] = std::move(a);
    out.integers[pk + "id_j"] = std::move(b);
    out.integers[pk + "layout"] = {0, size};
    out.bytes[pk + "history"] = std::move(h);
  }
  return out;
}

std::size_t seed_pair_histories(StateBlob& state, const StateBlob& saved,
                                const std::map<std::int64_t, std::int64_t>& renamed,
                                const std::string& file) {
  const auto& meta = state.i("meta");
  const auto& saved_meta = saved.i("meta");
  if (saved_meta.empty() || saved_meta[0] != meta.at(1))
    throw InputError(
        fmt::format("load_particles: {} holds {}D contact histories, this scene is {}D", file,
                    saved_meta.empty() ? 0 : saved_meta[0], meta.at(1)));
  const auto& particle_id = state.i("particles.id");
  std::unordered_map<std::int64_t, std::int64_t> index_of;
  for (std::size_t k = 0; k < particle_id.size(); ++k)
    index_of[particle_id[k]] = static_cast<std::int64_t>(k);
  auto rename = [&](std::int64_t id) {
    auto it = renamed.find(id);
    if (it == renamed.end())
      throw InputError(fmt::format(
          "load_particles: {} has a contact history for particle {}, which its snapshot lacks",
          file, id));
    return it->second;
  };
  if (saved.integers.count("rolling_springs") &&
      saved.i("rolling_springs") != std::vector<std::int64_t>{1})
    throw InputError(fmt::format(
        "load_particles: {} says its rolling springs hold a form this build does not know "
        "('rolling_springs' is not {{1}})",
        file));
  std::size_t seeded = 0;
  for (const std::string& pk : pair_prefixes(saved)) {
    if (!state.integers.count(pk + "layout"))
      throw InputError(fmt::format(
          "load_particles: {} holds histories of the contact model '{}', which this build lacks",
          file, model_of(pk)));
    const std::int64_t size = state.i(pk + "layout").at(1);
    if (saved.i(pk + "layout").at(1) != size)
      throw InputError(fmt::format(
          "load_particles: {} holds '{}' histories of {} bytes, this build's are {} bytes (written "
          "by another version?)",
          file, model_of(pk), saved.i(pk + "layout").at(1), size));
    auto& i = state.integers[pk + "i"];
    auto& j = state.integers[pk + "j"];
    auto& slot = state.integers[pk + "slot"];
    auto& id_i = state.integers[pk + "id_i"];
    auto& id_j = state.integers[pk + "id_j"];
    auto& history = state.bytes[pk + "history"];
    std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> listed;
    for (std::size_t k = 0; k < id_i.size(); ++k) listed[{id_i[k], id_j[k]}] = k;
    const auto& from_i = saved.i(pk + "id_i");
    const auto& from_j = saved.i(pk + "id_j");
    const auto& from_history = saved.b(pk + "history");
    if (from_j.size() != from_i.size() ||
        from_history.size() != from_i.size() * static_cast<std::size_t>(size))
      throw InputError(fmt::format(
          "load_particles: {}: the '{}' contact histories differ in length", file, model_of(pk)));
    for (std::size_t k = 0; k < from_i.size(); ++k) {
      const std::int64_t a = rename(from_i[k]), b = rename(from_j[k]);
      if (!(a < b))
        throw InputError(fmt::format(
            "load_particles: particles {} and {} of {} would be loaded as {} and {}, in the "
            "opposite order: their contact history (the force on the lower id) cannot be kept",
            from_i[k], from_j[k], file, a, b));
      const auto ia = index_of.find(a), ib = index_of.find(b);
      if (ia == index_of.end() || ib == index_of.end())
        throw InputError(fmt::format(
            "load_particles: particle {} or {} is not in this scene (loading {})", a, b, file));
      const auto first = from_history.begin() + static_cast<std::ptrdiff_t>(k * size);
      auto at = listed.find({a, b});
      if (at != listed.end()) {
        std::copy(first, first + size,
                  history.begin() + static_cast<std::ptrdiff_t>(at->second * size));
      } else {
        i.push_back(ia->second);
        j.push_back(ib->second);
        slot.push_back(0);  // taken afresh from the scene's pair table on loading
        id_i.push_back(a);
        id_j.push_back(b);
        history.insert(history.end(), first, first + size);
      }
      ++seeded;
    }
    state.bytes[pk + "track"].clear();  // tracking state is made afresh for every entry
  }
  // Lists of new lengths: give every list its own slot range again, and have
  // the next step rebuild them (carrying the histories by id pair).
  std::int64_t offset = 0;
  for (const char* kind : {"pairs.", "walls."}) {
    for (auto& entry : state.integers) {
      const std::string& k = entry.first;
      const std::string tail = ".layout";
      if (k.compare(0, std::string(kind).size(), kind) != 0 || k.size() <= tail.size() ||
          k.compare(k.size() - tail.size(), tail.size(), tail) != 0)
        continue;
      const std::string prefix = k.substr(0, k.size() - tail.size() + 1);
      const std::string count_key =
          std::string(kind) == "pairs." ? prefix + "i" : prefix + "particle";
      entry.second.at(0) = offset;
      offset += static_cast<std::int64_t>(state.i(count_key).size());
    }
  }
  state.integers["meta"].at(5) = 0;
  return seeded;
}

}  // namespace granule::io
