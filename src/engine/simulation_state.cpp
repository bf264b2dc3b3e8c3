// Simulation<D>::save_state / load_state: the complete state as plain arrays
// (core/state.hpp), so that a checkpointed run continues bit-identically.
// Everything the next step reads is saved, including the neighbour lists in
// their order (the order fixes the force sums) and the contact histories as
// raw bytes; derived buffers (the contact slots) are rebuilt from them.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <type_traits>

#include "core/errors.hpp"
#include "engine/simulation.hpp"
#include "engine/state_checks.hpp"
#include "neighbor/contact_lists.hpp"

namespace granule {

namespace {
constexpr std::int64_t state_version = 3;

template <typename T, typename A>
std::vector<std::uint8_t> raw_bytes(const std::vector<T, A>& v) {
  // Histories are structs of doubles, ints and fixed-size Eigen vectors: plain
  // memory, copied exactly. The element size is saved beside them and checked.
  std::vector<std::uint8_t> out(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size());
  return out;
}
template <typename T, typename A>
void from_raw_bytes(const std::vector<std::uint8_t>& in, std::vector<T, A>& v,
                    const std::string& what) {
  if (in.size() % sizeof(T) != 0)
    throw InputError(
        fmt::format("checkpoint: '{}' has {} bytes, not a whole number of {}-byte "
                    "records (written by another build?)",
                    what, in.size(), sizeof(T)));
  v.resize(in.size() / sizeof(T));
  if (!v.empty()) std::memcpy(static_cast<void*>(v.data()), in.data(), in.size());
}
// Whether histories of model M, written by builds that held the rolling
// spring's torque M_k (no "rolling_springs" entry), hold one wound where this
// build holds M_k / sqrt(k_r) (the law's stiffness follows the overlap): such
// a spring cannot be converted without its contact's k_r.
template <int D, typename M, typename A>
bool wound_as_torques(const std::vector<typename M::template History<D>, A>& histories) {
  if constexpr (has_rolling<M>::value) {
    if constexpr (M::rolling_spring_scaled) {
      for (const auto& h : histories)
        if (Dim<D>::spin_sq(h.rolling) > 0) return true;
    }
  }
  return false;
}
// A bucket's histories of `each` bytes: this build's records, or those of
// builds before the twisting torque (is_history_without_twisting), read with
// no twist held. Without `scaled_springs` (the checkpoint's "rolling_springs"
// entry) a wound spring of an older build is refused (wound_as_torques).
template <int D, typename M, typename A>
void read_histories(const std::vector<std::uint8_t>& in, std::int64_t each,
                    std::vector<typename M::template History<D>, A>& out, const std::string& what,
                    bool scaled_springs) {
  bool read = false;
  if constexpr (has_rolling<M>::value) {
    if (is_history_without_twisting<D, M>(each)) {
      std::vector<typename M::template HistoryWithoutTwisting<D>> old;
      from_raw_bytes(in, old, what);
      out.resize(old.size());
      for (std::size_t k = 0; k < old.size(); ++k)
        out[k] = M::from_history_without_twisting(old[k]);
      read = true;
    }
  }
  if (!read) {
    if (each != static_cast<std::int64_t>(sizeof(typename M::template History<D>)))
      throw InputError(
          fmt::format("checkpoint: {} histories have another layout (another build?)", M::name));
    from_raw_bytes(in, out, what);
  }
  if (!scaled_springs && wound_as_torques<D, M>(out))
    throw InputError(fmt::format(
        "checkpoint: '{}' holds {} rolling springs as torques (it has no 'rolling_springs' "
        "entry), as builds before this one did; this build holds them as M / sqrt(k_r) "
        "(docs/contact_models.md, \"Springs whose stiffness follows the overlap\") and cannot "
        "convert a wound one: restart with the build that wrote the checkpoint, or run the "
        "scene afresh",
        what, M::name));
}
template <typename T, typename A>
std::vector<std::int64_t> to_i64(const std::vector<T, A>& v) {
  return std::vector<std::int64_t>(v.begin(), v.end());
}
template <typename T>
std::vector<T> from_i64(const std::vector<std::int64_t>& v) {
  std::vector<T> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = static_cast<T>(v[k]);
  return out;
}
template <typename V, typename A>
std::vector<double> flatten(const std::vector<V, A>& v) {
  constexpr int width = sizeof(V) / sizeof(double);
  std::vector<double> out(v.size() * width);
  if (!v.empty()) std::memcpy(out.data(), v.data(), out.size() * sizeof(double));
  return out;
}
template <typename V, typename A>
void unflatten(const std::vector<double>& in, std::vector<V, A>& v, std::size_t count,
               const std::string& what) {
  constexpr std::size_t width = sizeof(V) / sizeof(double);
  if (in.size() != count * width)
    throw InputError(
        fmt::format("checkpoint: '{}' has {} values, expected {}", what, in.size(), count * width));
  v.resize(count);
  if (count) std::memcpy(static_cast<void*>(v.data()), in.data(), in.size() * sizeof(double));
}

}  // namespace

const std::vector<double>& StateBlob::d(const std::string& key) const {
  auto it = doubles.find(key);
  if (it == doubles.end()) throw InputError(fmt::format("checkpoint lacks '{}'", key));
  return it->second;
}
const std::vector<std::int64_t>& StateBlob::i(const std::string& key) const {
  auto it = integers.find(key);
  if (it == integers.end()) throw InputError(fmt::format("checkpoint lacks '{}'", key));
  return it->second;
}
const std::vector<std::uint8_t>& StateBlob::b(const std::string& key) const {
  auto it = bytes.find(key);
  if (it == bytes.end()) throw InputError(fmt::format("checkpoint lacks '{}'", key));
  return it->second;
}
const std::string& StateBlob::t(const std::string& key) const {
  auto it = texts.find(key);
  if (it == texts.end()) throw InputError(fmt::format("checkpoint lacks '{}'", key));
  return it->second;
}
std::vector<std::string> StateBlob::lines(const std::string& key) const {
  std::vector<std::string> out;
  std::istringstream in(t(key));
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

template <int D>
StateBlob Simulation<D>::save_state() const {
  StateBlob s;
  s.integers["meta"] = {
      state_version,       D, step_, p_.next_id, static_cast<std::int64_t>(rebuilds_),
      lists_valid_ ? 1 : 0};
  // A callback's change still to be prepared for (step() does it first): 1 in
  // full, 2 a law's parameters only (lists_kept_).
  s.integers["prepare_due"] = {prepared_ ? 0 : lists_kept_ ? 2 : 1};
  // The rolling springs hold M / sqrt(k_r) where k_r follows the overlap (rolling.hpp).
  s.integers["rolling_springs"] = {1};
  // The thin walls' crossing check runs on the step after a deep contact too.
  if (thin_deep_last_step_) s.integers["thin_deep_last_step"] = {1};
  s.doubles["meta"] = {time_,
                       dt_,
                       dt_fixed_,
                       steps_per_contact_,
                       skin_,
                       skin_set_,
                       max_displacement_sq_,
                       static_cast<double>(periodic_.axis),
                       periodic_.origin,
                       periodic_.length,
                       contact_reach_};
  // The clock's origin (time_ is computed from it, so a restart must take it over).
  s.doubles["clock"] = {clock_time_, clock_dt_};
  s.integers["clock"] = {clock_step_};
  // Materials and contact laws (their values printed exactly, %.17g).
  std::string names;
  std::vector<double> props;
  for (const auto& m : materials_) {
    names += m.name + "\n";
    props.insert(props.end(), {m.density, m.young, m.poisson, m.surface_energy});
  }
  s.texts["materials"] = names;
  s.doubles["materials"] = props;
  auto catalogue = contact_model_catalogue();
  std::string laws;
  for (int a = 0; a < pairs_.material_count(); ++a)
    for (int b = a; b < pairs_.material_count(); ++b) {
      const auto& e = pairs_.at(a, b);
      if (e.model < 0) continue;
      laws += fmt::format("{}\t{}\t{}", materials_[a].name, materials_[b].name,
                          catalogue[e.model].name);
      for (const auto& [k, v] : pairs_.values(a, b)) laws += fmt::format("\t{}={:.17g}", k, v);
      laws += "\n";
    }
  s.texts["contacts"] = laws;
  // Walls: their moving parts.
  std::string wall_names;
  std::vector<double> walls;
  for (const auto& w : walls_) {
    wall_names += w.name + "\n";
    Triple pt = to_triple(w.point), vel = to_triple(w.velocity),
           moved = to_triple(w.moved_since_rebuild);
    walls.insert(walls.end(), {pt[0], pt[1], pt[2], vel[0], vel[1], vel[2], w.angular_velocity,
                               moved[0], moved[1], moved[2]});
  }
  s.texts["walls"] = wall_names;
  s.doubles["walls"] = walls;
  save_meshes(s);  // simulation_meshes.cpp
  save_bonds(s);   // simulation_bonds.cpp
  // Body forces.
  {
    Triple g = to_triple(body_.gravity), c = to_triple(body_.central_point);
    s.doubles["body"] = {body_.gravity_on ? 1.0 : 0.0, g[0], g[1], g[2],
                         body_.central_on ? 1.0 : 0.0, c[0], c[1], c[2],
                         body_.central_strength};
  }
  if (damping_.active())
    s.doubles["damping"] = {damping_.viscous, damping_.spin, damping_.local_fraction};
  // Particles, in storage order.
  s.doubles["particles.position"] = flatten(p_.position);
  s.doubles["particles.velocity"] = flatten(p_.velocity);
  s.doubles["particles.spin"] = flatten(p_.spin);
  {
    std::vector<V> force(p_.size());
    std::vector<S> torque(p_.size());
    for (std::size_t i = 0; i < p_.size(); ++i)
      force[i] = p_.force_torque[i].force, torque[i] = p_.force_torque[i].torque;
    s.doubles["particles.force"] = flatten(force);
    s.doubles["particles.torque"] = flatten(torque);
  }
  s.doubles["particles.radius"] = flatten(p_.radius);
  s.doubles["particles.mass"] = flatten(p_.mass);
  s.doubles["particles.inv_mass"] = flatten(p_.inv_mass);
  s.doubles["particles.inv_inertia"] = flatten(p_.inv_inertia);
  s.doubles["particles.position_at_rebuild"] = flatten(position_at_rebuild_);
  s.integers["particles.id"] = p_.id;
  s.integers["particles.material"] = to_i64(p_.material);
  s.integers["particles.fixed"] = to_i64(p_.fixed);
  s.integers["particles.index_of_id"] = to_i64(p_.index_of_id);
  // Neighbour lists with their histories, per model. Lists whose storage
  // indices went stale (list_indices_stale_: a particle removed since they were
  // built) are written as their live entries (live_entries), slots laid out as a
  // rebuild lays them, pairs then walls: a checkpoint names only particles it
  // holds (state_checks.cpp), and the next step rebuilds the lists anyway.
  typename BucketsOf<D, ContactModels>::pairs live_pairs;
  typename BucketsOf<D, ContactModels>::walls live_walls;
  if (list_indices_stale_) {
    std::size_t slots = 0;
    for_each_model([&](auto index) {
      constexpr int I = decltype(index)::value;
      auto& b = std::get<I>(live_pairs) = live_entries(std::get<I>(pair_buckets_), p_);
      b.offset = slots;
      slots += b.size();
    });
    for_each_model([&](auto index) {
      constexpr int I = decltype(index)::value;
      auto& b = std::get<I>(live_walls) = live_entries(std::get<I>(wall_buckets_), p_);
      b.offset = slots;
      slots += b.size();
    });
  }
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const std::string pk = fmt::format("pairs.{}.", M::name),
                      wk = fmt::format("walls.{}.", M::name);
    const auto& pb = list_indices_stale_ ? std::get<I>(live_pairs) : std::get<I>(pair_buckets_);
    s.integers[pk + "i"] = to_i64(pb.i);
    s.integers[pk + "j"] = to_i64(pb.j);
    s.integers[pk + "slot"] = to_i64(pb.slot);
    s.integers[pk + "id_i"] = pb.id_i;
    s.integers[pk + "id_j"] = pb.id_j;
    s.integers[pk + "layout"] = {
        static_cast<std::int64_t>(pb.offset),
        static_cast<std::int64_t>(sizeof(typename M::template History<D>))};
    s.bytes[pk + "history"] = raw_bytes(pb.history);
    s.bytes[pk + "track"] = raw_bytes(pb.track);
    const auto& wb = list_indices_stale_ ? std::get<I>(live_walls) : std::get<I>(wall_buckets_);
    s.integers[wk + "particle"] = to_i64(wb.particle);
    s.integers[wk + "wall"] = to_i64(wb.wall);
    s.integers[wk + "slot"] = to_i64(wb.slot);
    s.integers[wk + "id"] = wb.id;
    s.integers[wk + "part"] = to_i64(wb.part);
    s.doubles[wk + "part_normal"] = flatten(wb.part_normal);
    s.integers[wk + "layout"] = {
        static_cast<std::int64_t>(wb.offset),
        static_cast<std::int64_t>(sizeof(typename M::template History<D>))};
    s.bytes[wk + "history"] = raw_bytes(wb.history);
    s.bytes[wk + "track"] = raw_bytes(wb.track);
  });
  save_last_step(s);
  // Hooks: when each fires next (matched by name and order on load).
  std::string hook_names;
  std::vector<double> origin;
  std::vector<std::int64_t> periods;
  for (const auto& h : hooks_) {
    hook_names += h.name + "\n";
    origin.push_back(h.origin_time);
    periods.push_back(h.periods);
  }
  s.texts["hooks"] = hook_names;
  s.doubles["hooks.origin_time"] = origin;
  s.integers["hooks.periods"] = periods;
  save_schedules(s);  // simulation_schedules.cpp
  // The guards' memory: whether deep overlaps are still the scene's own (an overlapping
  // fill relaxing, not a pass-through) and whether the one overlap warning was given;
  // and the pair that set the automatic time step, for the run's description.
  s.integers["guards"] = {scene_overlaps_ ? 1 : 0, overlap_warned_ ? 1 : 0};
  s.integers["guards.wall_overlap_warned"] = {wall_overlap_warned_ ? 1 : 0};
  // Whom the grace is for, when particles placed mid-run have it and the rest not:
  // without it a restart would excuse every pair until all are clear.
  if (scene_overlaps_ && !grace_for_all_) {
    std::vector<std::int64_t> placed = placed_ids_;
    std::sort(placed.begin(), placed.end());
    placed.erase(std::unique(placed.begin(), placed.end()), placed.end());
    s.integers["guards.placed_ids"] = placed;
  }
  s.texts["time_step.governing_pair"] = dt_governing_pair_;
  s.integers["time_step.per_contact"] = {dt_per_contact_ ? 1 : 0};
  // A state a failed run left (a caught failure) may hold a particle escaped
  // through a wall, which load_state refuses in any other checkpoint.
  if (failed_at_step_ == step_ && escaped_particle_and_wall().first >= 0)
    s.integers["guards.failed_at_step"] = {step_};
  // The lists above are in this order: a restart must keep it to sum the same way.
  s.integers["canonical_order"] = {canonical_order_ ? 1 : 0};
  return s;
}

template <int D>
std::string Simulation<D>::wound_legacy_rolling_springs(const StateBlob& saved) const {
  std::string found;
  if (saved.integers.count("rolling_springs")) return found;
  for_each_model([&](auto index) {
    using M = ContactModelAt<decltype(index)::value>;
    if constexpr (has_rolling<M>::value) {
      if constexpr (M::rolling_spring_scaled) {
        const std::string pk = fmt::format("pairs.{}.", M::name);
        // Records of another size are refused by the seeding itself.
        if (!found.empty() || !saved.bytes.count(pk + "history") ||
            !saved.integers.count(pk + "layout") || saved.i(pk + "layout").size() < 2 ||
            !is_known_history_layout<D, M>(saved.i(pk + "layout")[1]))
          return;
        std::vector<typename M::template History<D>> h;
        read_histories<D, M>(saved.b(pk + "history"), saved.i(pk + "layout")[1], h, pk + "history",
                             true);
        if (wound_as_torques<D, M>(h)) found = M::name;
      }
    }
  });
  return found;
}

template <int D>
void Simulation<D>::load_state(const StateBlob& s) {
  const auto& meta = s.i("meta");
  if (meta.size() != 6)
    refuse_entry("meta", fmt::format("has {} integers, expected 6", meta.size()));
  if (meta[0] != state_version)
    refuse_entry("meta", fmt::format("holds state version {} (this build reads {})", meta[0],
                                     state_version));
  if (meta[1] != 2 && meta[1] != 3)
    refuse_entry("meta", fmt::format("holds dimension {}, not 2 or 3", meta[1]));
  if (meta[1] != D)
    throw InputError(
        fmt::format("checkpoint holds a {}D simulation, this scene is {}D", meta[1], D));
  // The scene must have declared the same materials and walls, in the same order.
  const auto names = s.lines("materials");
  if (names.size() != materials_.size())
    throw InputError(fmt::format("checkpoint has {} materials, the scene declares {}", names.size(),
                                 materials_.size()));
  for (std::size_t m = 0; m < names.size(); ++m)
    if (names[m] != materials_[m].name)
      throw InputError(fmt::format("checkpoint material {} is '{}', the scene's is '{}'", m,
                                   names[m], materials_[m].name));
  const auto wall_names = s.lines("walls");
  if (wall_names.size() != walls_.size())
    throw InputError(fmt::format("checkpoint has {} walls, the scene declares {}",
                                 wall_names.size(), walls_.size()));
  for (std::size_t w = 0; w < wall_names.size(); ++w)
    if (wall_names[w] != walls_[w].name)
      throw InputError(fmt::format("checkpoint wall {} is '{}', the scene's is '{}'", w,
                                   wall_names[w], walls_[w].name));

  check_state<D>(s, materials_.size(), walls_.size());
  ParallelBonds<D> bonds = read_bonds(s);  // simulation_bonds.cpp
  BondMotionState bond_motion = read_bond_motion(s, bonds.size());
  const auto& md = s.d("meta");
  time_ = md[0], dt_ = md[1], dt_fixed_ = md[2], steps_per_contact_ = md[3];
  dt_from_time_ = time_;
  clock_time_ = s.d("clock")[0], clock_dt_ = s.d("clock")[1], clock_step_ = s.i("clock")[0];
  skin_ = md[4], skin_set_ = md[5], max_displacement_sq_ = md[6];
  periodic_ = {static_cast<int>(md[7]), md[8], md[9]};
  contact_reach_ = md[10];
  step_ = meta[2];
  dt_from_step_ = step_;
  rebuilds_ = static_cast<std::size_t>(meta[4]);
  // Pruned pair lists are not saved (they change no result): note them all afresh.
  prune_travel_ = std::numeric_limits<double>::infinity();

  const auto& props = s.d("materials");
  if (props.size() != 4 * materials_.size()) throw InputError("checkpoint: material properties");
  for (std::size_t m = 0; m < materials_.size(); ++m) {
    materials_[m].density = props[4 * m];
    materials_[m].young = props[4 * m + 1];
    materials_[m].poisson = props[4 * m + 2];
    materials_[m].surface_energy = props[4 * m + 3];
  }
  for (const auto& line : s.lines("contacts")) {
    std::vector<std::string> f;
    std::istringstream in(line);
    for (std::string x; std::getline(in, x, '\t');) f.push_back(x);
    if (f.size() < 3) throw InputError(fmt::format("checkpoint: bad contact line '{}'", line));
    ParamValues values;
    for (std::size_t k = 3; k < f.size(); ++k) {
      auto eq = f[k].find('=');
      if (eq == std::string::npos)
        throw InputError(fmt::format("checkpoint: bad value '{}'", f[k]));
      const std::string text = f[k].substr(eq + 1);
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(
            fmt::format("checkpoint: 'contacts' value '{}' is not a finite number", f[k]));
      values[f[k].substr(0, eq)] = v;
    }
    try {
      set_contact(f[0], f[1], f[2], values);
    } catch (const InputError& e) {
      throw InputError(fmt::format("checkpoint: 'contacts' line '{}': {}", line, e.what()));
    }
  }
  const auto& walls = s.d("walls");
  if (walls.size() != 10 * walls_.size()) throw InputError("checkpoint: wall state");
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const double* x = &walls[10 * w];
    walls_[w].point = to_vec({x[0], x[1], x[2]});
    walls_[w].velocity = to_vec({x[3], x[4], x[5]});
    walls_[w].angular_velocity = x[6];
    walls_[w].moved_since_rebuild = to_vec({x[7], x[8], x[9]});
    if (walls_[w].finite()) walls_[w].center = walls_[w].point;  // they move together
  }
  const auto& body = s.d("body");
  if (body.size() != 9) throw InputError("checkpoint: body forces");
  body_.gravity_on = body[0] != 0;
  body_.gravity = to_vec({body[1], body[2], body[3]});
  body_.central_on = body[4] != 0;
  body_.central_point = to_vec({body[5], body[6], body[7]});
  body_.central_strength = body[8];
  // Absent: damping was off (a checkpoint of a scene without it, or of an older build).
  const auto damping = s.doubles.find("damping");
  damping_ = damping == s.doubles.end()
                 ? Damping{}
                 : Damping{damping->second[0], damping->second[1], damping->second[2]};
  // The periodic axis the field ignores (body_forces.hpp), which prepare() also sets:
  // a checkpoint taken mid-run resumes without it.
  body_.periodic_axis = periodic_.on() ? periodic_.axis : -1;

  const std::size_t n = s.i("particles.id").size();
  p_.id = s.i("particles.id");
  p_.material = from_i64<std::int32_t>(s.i("particles.material"));
  p_.fixed = from_i64<std::uint8_t>(s.i("particles.fixed"));
  p_.index_of_id = from_i64<std::int32_t>(s.i("particles.index_of_id"));
  p_.next_id = meta[3];
  unflatten(s.d("particles.position"), p_.position, n, "particles.position");
  unflatten(s.d("particles.velocity"), p_.velocity, n, "particles.velocity");
  unflatten(s.d("particles.spin"), p_.spin, n, "particles.spin");
  {
    std::vector<V> force;
    std::vector<S> torque;
    unflatten(s.d("particles.force"), force, n, "particles.force");
    unflatten(s.d("particles.torque"), torque, n, "particles.torque");
    p_.force_torque.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      p_.force_torque[i].force = force[i], p_.force_torque[i].torque = torque[i];
  }
  unflatten(s.d("particles.position_at_rebuild"), position_at_rebuild_, n,
            "particles.position_at_rebuild");
  unflatten(s.d("particles.radius"), p_.radius, n, "particles.radius");
  unflatten(s.d("particles.mass"), p_.mass, n, "particles.mass");
  unflatten(s.d("particles.inv_mass"), p_.inv_mass, n, "particles.inv_mass");
  unflatten(s.d("particles.inv_inertia"), p_.inv_inertia, n, "particles.inv_inertia");
  if (p_.material.size() != n || p_.fixed.size() != n ||
      p_.index_of_id.size() != static_cast<std::size_t>(p_.next_id))
    throw InputError("checkpoint: particle arrays differ in length");
  // What a run itself tolerates (check_escapes): a free particle pressed into a wall
  // may have its centre beyond it, by less than its radius, and still be pushed back;
  // one further beyond has escaped, and only a failed run leaves such a state (its
  // checkpoint says so, and the next run stops there again, as the whole run did).
  const bool failed_state = s.integers.count("guards.failed_at_step") != 0;  // check_state
  failed_at_step_ = failed_state ? step_ : -1;
  if (const auto [i, w] = escaped_particle_and_wall(); i >= 0 && !failed_state)
    refuse_entry("particles.position",
                 fmt::format("particle {} at ({}) lies beyond wall '{}' by more than its radius",
                             p_.id[i], fmt::join(to_triple(p_.position[i]), ", "), walls_[w].name));

  // What the rolling springs hold: absent in checkpoints of builds that held
  // M_k; this build writes {1}.
  const bool scaled_springs = s.integers.count("rolling_springs") > 0;
  if (scaled_springs && s.i("rolling_springs") != std::vector<std::int64_t>{1})
    refuse_entry("rolling_springs", "is not {1}, the one form this build knows");
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const std::string pk = fmt::format("pairs.{}.", M::name),
                      wk = fmt::format("walls.{}.", M::name);
    auto& pb = std::get<I>(pair_buckets_);
    const auto& pl = s.i(pk + "layout");
    if (pl.size() != 2)
      throw InputError(
          fmt::format("checkpoint: {} histories have another layout (another build?)", M::name));
    const auto assign = [](auto& to, const std::vector<std::uint32_t>& from) {
      to.assign(from.begin(), from.end());
    };
    assign(pb.i, from_i64<std::uint32_t>(s.i(pk + "i")));
    assign(pb.j, from_i64<std::uint32_t>(s.i(pk + "j")));
    assign(pb.slot, from_i64<std::uint32_t>(s.i(pk + "slot")));
    pb.id_i = s.i(pk + "id_i");
    pb.id_j = s.i(pk + "id_j");
    pb.offset = static_cast<std::size_t>(pl[0]);
    read_histories<D, M>(s.b(pk + "history"), pl[1], pb.history, pk + "history", scaled_springs);
    from_raw_bytes(s.b(pk + "track"), pb.track, pk + "track");
    auto& wb = std::get<I>(wall_buckets_);
    const auto& wl = s.i(wk + "layout");
    if (wl.size() != 2)
      throw InputError(fmt::format("checkpoint: {} histories have another layout", M::name));
    wb.particle = from_i64<std::uint32_t>(s.i(wk + "particle"));
    wb.wall = from_i64<std::uint32_t>(s.i(wk + "wall"));
    wb.slot = from_i64<std::uint32_t>(s.i(wk + "slot"));
    wb.id = s.i(wk + "id");
    wb.part = from_i64<std::uint8_t>(s.i(wk + "part"));
    unflatten(s.d(wk + "part_normal"), wb.part_normal, wb.part.size(), wk + "part_normal");
    wb.offset = static_cast<std::size_t>(wl[0]);
    read_histories<D, M>(s.b(wk + "history"), wl[1], wb.history, wk + "history", scaled_springs);
    from_raw_bytes(s.b(wk + "track"), wb.track, wk + "track");
    const std::size_t np = pb.i.size(), nw = wb.particle.size();
    if (pb.j.size() != np || pb.slot.size() != np || pb.id_i.size() != np || pb.id_j.size() != np ||
        pb.history.size() != np || wb.wall.size() != nw || wb.slot.size() != nw ||
        wb.id.size() != nw || wb.history.size() != nw || wb.part.size() != nw ||
        wb.part_normal.size() != nw)
      throw InputError(fmt::format("checkpoint: {} contact lists differ in length", M::name));
    // Parameter slots come from this scene's pair table (the laws were just restored),
    // and every listed contact must still be governed by this model.
    for (std::size_t k = 0; k < np; ++k) {
      if (pb.i[k] >= n || pb.j[k] >= n)
        throw InputError("checkpoint: a contact names a particle that does not exist");
      const auto& e = pairs_.at(p_.material[pb.i[k]], p_.material[pb.j[k]]);
      if (e.model != I) throw InputError("checkpoint: contact laws differ from the scene's");
      pb.slot[k] = static_cast<std::uint32_t>(e.slot);
    }
    pb.law = -2;  // the slots are new
    for (std::size_t k = 0; k < nw; ++k) {
      if (wb.particle[k] >= n || wb.wall[k] >= walls_.size())
        throw InputError("checkpoint: a wall contact names a particle or wall that does not exist");
      const auto& e = pairs_.at(p_.material[wb.particle[k]], walls_[wb.wall[k]].material);
      if (e.model != I) throw InputError("checkpoint: contact laws differ from the scene's");
      wb.slot[k] = static_cast<std::uint32_t>(e.slot);
    }
    // Tracking state only if this scene tracks events now.
    if (!tracking_) pb.track.clear(), wb.track.clear();
    if (tracking_ && pb.track.size() != np) pb.track.assign(np, {});
    if (tracking_ && wb.track.size() != nw) wb.track.assign(nw, {});
  });
  load_meshes(s);  // simulation_meshes.cpp
  bonds_ = std::move(bonds);
  bond_moved_with_ = std::move(bond_motion.moved_with);
  bonds_unmoved_from_ = bond_motion.unmoved_from;
  build_slots();

  const auto hook_names = s.lines("hooks");
  const auto& origin = s.d("hooks.origin_time");
  const auto& periods = s.i("hooks.periods");
  for (std::size_t h = 0; h < hooks_.size() && h < hook_names.size(); ++h)
    if (hooks_[h].name == hook_names[h]) {
      // A time hook due past its next period (or a step hook with a period) is no state
      // this build writes: refused, naming the entry, rather than a callback silenced.
      const Hook& hook = hooks_[h];
      const bool timed = hook.every_time > 0;
      const double next = origin[h] + static_cast<double>(periods[h]) * hook.every_time;
      if (timed
              ? periods[h] < 1 || !(origin[h] <= time_) || !(next <= time_ + hook.every_time + dt_)
              : periods[h] != 0 || origin[h] != 0)
        refuse_entry("hooks.periods",
                     fmt::format("hook '{}' next due at {} s (origin {} s, {} periods): not "
                                 "within a period of the time, {} s",
                                 hook.name, next, origin[h], periods[h], time_));
      hooks_[h].origin_time = origin[h];
      hooks_[h].periods = periods[h];
    }
  load_schedules(s);  // simulation_schedules.cpp
  load_last_step(s);

  lists_valid_ = meta[5] != 0;
  list_indices_stale_ = false;  // save_state wrote live entries
  arm_overlap_grace(s.i("guards")[0] != 0);
  const auto placed = s.integers.find("guards.placed_ids");  // checked by check_state
  if (scene_overlaps_ && placed != s.integers.end()) {
    grace_for_all_ = false;
    arm_overlap_grace_for(placed->second);
  }
  overlap_warned_ = s.i("guards")[1] != 0;
  const auto wall_warned = s.integers.find("guards.wall_overlap_warned");  // checked by check_state
  wall_overlap_warned_ = wall_warned != s.integers.end() && wall_warned->second[0] == 1;
  dt_governing_pair_ = s.t("time_step.governing_pair");
  const auto canonical = s.integers.find("canonical_order");  // checked by check_state
  canonical_order_ = canonical != s.integers.end() && canonical->second[0] == 1;
  // The same limit prepare() holds a run to before its first step, for the laws
  // and particles just loaded (prepare() itself would rebuild the lists and so
  // change the order of the force sums).
  if (p_.size()) {
    TimeStepReport rule = time_step_rule();
    // As saved (checked by check_state); an older build's checkpoint: the governing
    // pair's kind, as the rule finds it now.
    const auto per_contact = s.integers.find("time_step.per_contact");
    dt_per_contact_ =
        per_contact != s.integers.end() ? per_contact->second[0] == 1 : rule.per_contact;
    deep_modes_ = std::move(rule.deep_modes);  // the deep-contact check's, as prepare() sets them
    deep_checked_pair_ = deep_checked_wall_ = 0;
    deep_rescan_step_ = -1;
    if (!(dt_ < rule.stability_limit))
      throw InputError(fmt::format(
          "checkpoint: 'meta' time_step {:.4g} s is above the stability limit {:.4g} s of {}: "
          "refused",
          dt_, rule.stability_limit, rule.limit_pair));
  }
  // What prepare() would have noted, for a checkpoint that needs none: the
  // step-over checks' radii, the time-step rule's kind, whether spins are integrated.
  note_smallest_radii();
  if (p_.size()) rotation_ = effects().rotation;
  const auto& prepare_due = s.i("prepare_due");
  if (prepare_due.size() != 1 || prepare_due[0] < 0 || prepare_due[0] > 2)
    refuse_entry("prepare_due",
                 fmt::format("holds {} values, not one of 0, 1 or 2", prepare_due.size()));
  prepared_ = prepare_due[0] == 0;
  thin_deep_last_step_ = s.integers.count("thin_deep_last_step") != 0;
  lists_kept_ = prepare_due[0] == 2;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
