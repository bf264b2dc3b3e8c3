// The checks load_state makes of a checkpoint before it takes any of it.
#include "engine/state_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "engine/simulation.hpp"

namespace granule {

[[noreturn]] void refuse_entry(const std::string& key, const std::string& why) {
  throw InputError(fmt::format("checkpoint: '{}' {}", key, why));
}

namespace {

// Positions, velocities and spins beyond 1e100 are far outside any scene, and
// their squares (separations, energies) would overflow to inf within a step.
constexpr double largest_kinematic = 1e100;

// `count` values, as many as `reference` (another entry) implies.
std::string expected_size(std::size_t size, std::size_t count, const std::string& reference) {
  return fmt::format("has {} values, expected {}{}", size, count,
                     reference.empty() ? "" : fmt::format(" (from '{}')", reference));
}
const std::vector<double>& doubles_of(const StateBlob& s, const std::string& key, std::size_t count,
                                      const std::string& reference = "") {
  const auto& v = s.d(key);
  if (v.size() != count) refuse_entry(key, expected_size(v.size(), count, reference));
  return v;
}
const std::vector<std::int64_t>& integers_of(const StateBlob& s, const std::string& key,
                                             std::size_t count, const std::string& reference = "") {
  const auto& v = s.i(key);
  if (v.size() != count) refuse_entry(key, expected_size(v.size(), count, reference));
  return v;
}
void all_finite(const std::vector<double>& v, const std::string& key, double bound) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k]) || std::abs(v[k]) > bound)
      refuse_entry(key, fmt::format("value {} is {}: must be finite{}", k, number_text(v[k]),
                                    bound < std::numeric_limits<double>::max()
                                        ? fmt::format(" and within +-{:g}", bound)
                                        : ""));
}
void all_positive(const std::vector<double>& v, const std::string& key) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!(std::isfinite(v[k]) && v[k] > 0))
      refuse_entry(key, fmt::format("value {} is {}: must be positive and finite", k, v[k]));
}
// Each value's index k must lie in [0, limit).
void all_below(const std::vector<std::int64_t>& v, std::int64_t limit, const std::string& key,
               const char* what) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (v[k] < 0 || v[k] >= limit)
      refuse_entry(key,
                   fmt::format("entry {} is {}: not a {} (there are {})", k, v[k], what, limit));
}
// 1/x as the engine stores it (0 for a fixed particle), to the rounding of one division.
// `of_keys` name the entries `of` comes from: one of them or `key` is damaged.
void inverse_of(const std::vector<double>& inv, const std::vector<double>& of,
                const std::vector<std::int64_t>& fixed, const std::string& key, const char* what,
                const char* of_keys) {
  for (std::size_t k = 0; k < inv.size(); ++k) {
    const double expected = fixed[k] ? 0.0 : 1.0 / of[k];
    if (!std::isfinite(inv[k]) || std::abs(inv[k] - expected) > 1e-12 * std::abs(expected))
      refuse_entry(key, fmt::format("value {} is {}, but the particle's {} ({}) gives {}", k,
                                    inv[k], what, of_keys, expected));
  }
}

}  // namespace

template <int D>
void check_state(const StateBlob& s, std::size_t material_count, std::size_t wall_count) {
  constexpr std::size_t spin_width = D == 2 ? 1 : 3;
  const auto& meta = s.i("meta");  // version and dimension: checked by load_state
  if (meta.size() != 6)
    refuse_entry("meta", fmt::format("has {} integers, expected 6", meta.size()));
  if (meta[2] < 0) refuse_entry("meta", fmt::format("step {} is negative", meta[2]));
  if (meta[4] < 0) refuse_entry("meta", fmt::format("rebuild count {} is negative", meta[4]));
  if (meta[5] != 0 && meta[5] != 1)
    refuse_entry("meta", fmt::format("lists-valid flag {} is neither 0 nor 1", meta[5]));
  const auto& md = doubles_of(s, "meta", 11);
  const char* meta_names[] = {"time",
                              "time_step",
                              "time_step set",
                              "steps_per_contact",
                              "skin",
                              "skin set",
                              "max_displacement_sq",
                              "periodic axis",
                              "periodic origin",
                              "periodic length",
                              "contact_reach"};
  for (std::size_t k = 0; k < md.size(); ++k)
    if (!std::isfinite(md[k])) refuse_entry("meta", fmt::format("{} is {}", meta_names[k], md[k]));
  auto at_least = [&](std::size_t k, double low, bool strictly) {
    if (strictly ? !(md[k] > low) : !(md[k] >= low))
      refuse_entry("meta", fmt::format("{} is {}: must be {} {}", meta_names[k], md[k],
                                       strictly ? ">" : ">=", low));
  };
  at_least(0, 0, false);  // time
  at_least(1, 0, true);   // time step (below the stability limit: load_state, once loaded)
  at_least(2, 0, false);
  at_least(3, 1, false);  // as set_steps_per_contact requires
  at_least(4, 0, false);
  at_least(5, 0, false);
  at_least(6, 0, false);
  at_least(10, 0, false);
  if (!(md[7] == -1 || md[7] == 0 || md[7] == 1 || (D == 3 && md[7] == 2)))
    refuse_entry("meta",
                 fmt::format("periodic axis {} is not -1 (none) or an axis below {}", md[7], D));
  const int axis = static_cast<int>(md[7]);
  if (axis >= 0 && !(md[9] > 0))
    refuse_entry("meta", fmt::format("periodic length {} must be > 0", md[9]));
  // A set time step is the one in use (prepare() makes it so).
  if (md[2] > 0 && md[1] != md[2])
    refuse_entry("meta",
                 fmt::format("time_step {} differs from the time_step set, {}", md[1], md[2]));

  const auto& props = doubles_of(s, "materials", 4 * material_count);
  for (std::size_t m = 0; m < material_count; ++m) {
    const double* x = &props[4 * m];
    if (!(std::isfinite(x[0]) && x[0] >= 0 && std::isfinite(x[1]) && x[1] >= 0 &&
          std::isfinite(x[3]) && x[3] >= 0 && std::isfinite(x[2]) && x[2] > -1 &&
          x[2] < 0.5 + 1e-12))
      refuse_entry("materials",
                   fmt::format("material {} has density {}, young {}, poisson {}, "
                               "surface_energy {}: as add_material requires, each must "
                               "be >= 0 (poisson in (-1, 0.5])",
                               m, x[0], x[1], x[2], x[3]));
  }
  all_finite(doubles_of(s, "walls", 10 * wall_count), "walls", largest_kinematic);
  const auto& body = doubles_of(s, "body", 9);
  all_finite(body, "body", largest_kinematic);
  if ((body[0] != 0 && body[0] != 1) || (body[4] != 0 && body[4] != 1) || body[8] < 0)
    refuse_entry("body", "flags must be 0 or 1 and the central strength >= 0");
  if (s.doubles.count("damping")) {  // optional: only a scene with damping on saves it
    const auto& damping = doubles_of(s, "damping", 3);
    if (!(std::isfinite(damping[0]) && damping[0] >= 0 && std::isfinite(damping[1]) &&
          damping[1] >= 0 && std::isfinite(damping[2]) && damping[2] >= 0 && damping[2] < 1))
      refuse_entry("damping", "the rates must be >= 0 and the local fraction in [0, 1)");
  }

  // Particles: every array as long as the id list, ids and their index table inverse
  // to each other.
  const std::size_t n = s.i("particles.id").size();
  const auto& id = s.i("particles.id");
  const std::int64_t next_id = meta[3];
  if (next_id < static_cast<std::int64_t>(n) || next_id >= (std::int64_t{1} << 31))
    refuse_entry("meta",
                 fmt::format("next id {} is below the particle count {} or too large", next_id, n));
  all_below(id, next_id, "particles.id", "particle id");
  const auto& index_of_id =
      integers_of(s, "particles.index_of_id", static_cast<std::size_t>(next_id), "meta");
  for (std::size_t k = 0; k < index_of_id.size(); ++k)
    if (index_of_id[k] < -1 || index_of_id[k] >= static_cast<std::int64_t>(n))
      refuse_entry("particles.index_of_id",
                   fmt::format("entry {} is {}: not -1 (removed) or one of the {} particles of "
                               "'particles.id'",
                               k, index_of_id[k], n));
  std::size_t live = 0;
  for (auto x : index_of_id) live += x >= 0;
  if (live != n)
    refuse_entry("particles.index_of_id", fmt::format("names {} particles, there are {}", live, n));
  for (std::size_t i = 0; i < n; ++i)
    if (index_of_id[static_cast<std::size_t>(id[i])] != static_cast<std::int64_t>(i))
      refuse_entry("particles.id",
                   fmt::format("entry {} is id {}, which the index table puts at {}", i, id[i],
                               index_of_id[static_cast<std::size_t>(id[i])]));
  const std::string ids = "particles.id";
  all_below(integers_of(s, "particles.material", n, ids), static_cast<std::int64_t>(material_count),
            "particles.material", "material");
  const auto& fixed = integers_of(s, "particles.fixed", n, ids);
  all_below(fixed, 2, "particles.fixed", "flag 0 or 1");
  for (const char* key : {"particles.position", "particles.velocity",
                          "particles.position_at_rebuild", "particles.force"})
    all_finite(doubles_of(s, key, n * D, ids), key, largest_kinematic);
  for (const char* key : {"particles.spin", "particles.torque"})
    all_finite(doubles_of(s, key, n * spin_width, ids), key, largest_kinematic);
  const auto& radius = doubles_of(s, "particles.radius", n, ids);
  const auto& mass = doubles_of(s, "particles.mass", n, ids);
  all_positive(radius, "particles.radius");
  all_positive(mass, "particles.mass");
  std::vector<double> inertia(n);
  for (std::size_t i = 0; i < n; ++i) inertia[i] = sphere_inertia(mass[i], radius[i]);
  inverse_of(doubles_of(s, "particles.inv_mass", n, ids), mass, fixed, "particles.inv_mass", "mass",
             "'particles.mass'");
  inverse_of(doubles_of(s, "particles.inv_inertia", n, ids), inertia, fixed,
             "particles.inv_inertia", "moment of inertia 0.4 m r^2",
             "'particles.mass', 'particles.radius'");
  // The skin in use is the one prepare() chose: the set one (or twice the adhesive
  // contacts' reach), and in any case beyond 1.5 times that reach, or contacts would be
  // lost from the lists while they still pull.
  {
    const double skin = md[4], skin_set = md[5], reach = md[10];
    if (n > 0 && !(skin > 1.5 * reach && skin > 0))
      refuse_entry("meta",
                   fmt::format("skin {} is not above 1.5 times the contact reach {}", skin, reach));
    if (skin_set > 0 && skin != skin_set && skin != 2 * reach)
      refuse_entry("meta", fmt::format("skin {} is not the skin set, {}", skin, skin_set));
  }
  if (axis >= 0) {
    // The force loops take minimum images of separations below 1.5 lengths
    // (Periodicity::wrap): positions must lie in (or just beside) the box.
    const auto& x = s.d("particles.position");
    for (std::size_t i = 0; i < n; ++i) {
      const double c = x[i * D + static_cast<std::size_t>(axis)];
      if (c < md[8] - 0.25 * md[9] || c > md[8] + 1.25 * md[9])
        refuse_entry("particles.position",
                     fmt::format("particle {} lies at {} along the periodic axis, outside the box "
                                 "[{}, {}]",
                                 id[i], c, md[8], md[8] + md[9]));
    }
  }

  // Contact lists: particles and walls that exist, each pair oriented (id i < id j,
  // the history's sign convention) and listed once, ids matching the particles, and
  // the slots of all lists apart.
  std::vector<std::pair<std::size_t, std::size_t>> slot_ranges;
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    using M = ContactModelAt<I>;
    const std::string pk = fmt::format("pairs.{}.", M::name),
                      wk = fmt::format("walls.{}.", M::name);
    for (const std::string& prefix : {pk, wk}) {
      const std::string key = prefix + "layout";
      const auto& layout = s.i(key);
      if (layout.size() != 2 || !is_known_history_layout<D, M>(layout[1]))
        refuse_entry(
            key, fmt::format("describes {} histories of another layout (another build?)", M::name));
      if (layout[0] < 0 || layout[0] >= (std::int64_t{1} << 30))
        refuse_entry(key, fmt::format("slot offset {} is out of range", layout[0]));
    }
    const std::size_t np = s.i(pk + "i").size();
    const auto& pi = s.i(pk + "i");
    const auto& pj = integers_of(s, pk + "j", np, pk + "i");
    const auto& id_i = integers_of(s, pk + "id_i", np, pk + "i");
    const auto& id_j = integers_of(s, pk + "id_j", np, pk + "i");
    // Slots are taken afresh from the scene's pair table; stored ones must still be slots.
    all_below(integers_of(s, pk + "slot", np, pk + "i"), std::int64_t{1} << 30, pk + "slot",
              "parameter slot");
    all_below(pi, static_cast<std::int64_t>(n), pk + "i", "particle index");
    all_below(pj, static_cast<std::int64_t>(n), pk + "j", "particle index");
    std::vector<std::pair<std::int64_t, std::int64_t>> seen(np);
    for (std::size_t k = 0; k < np; ++k) {
      const auto a = static_cast<std::size_t>(pi[k]), b = static_cast<std::size_t>(pj[k]);
      if (id_i[k] != id[a])
        refuse_entry(pk + "id_i", fmt::format("entry {} is not particle {}'s id", k, a));
      if (id_j[k] != id[b])
        refuse_entry(pk + "id_j", fmt::format("entry {} is not particle {}'s id", k, b));
      if (!(id[a] < id[b]))
        refuse_entry(pk + "i",
                     fmt::format("contact {} pairs ids {} and {}: not in increasing order", k,
                                 id[a], id[b]));
      seen[k] = {id[a], id[b]};
    }
    std::sort(seen.begin(), seen.end());
    if (std::adjacent_find(seen.begin(), seen.end()) != seen.end())
      refuse_entry(pk + "i", "lists a pair of particles twice");
    const std::size_t nw = s.i(wk + "particle").size();
    const auto& wp = s.i(wk + "particle");
    const auto& ww = integers_of(s, wk + "wall", nw, wk + "particle");
    const auto& wid = integers_of(s, wk + "id", nw, wk + "particle");
    all_below(integers_of(s, wk + "slot", nw, wk + "particle"), std::int64_t{1} << 30, wk + "slot",
              "parameter slot");
    all_below(wp, static_cast<std::int64_t>(n), wk + "particle", "particle index");
    all_below(ww, static_cast<std::int64_t>(wall_count), wk + "wall", "wall");
    // A mesh wall lists a particle once per part (kernel/mesh_contacts.hpp).
    const auto& wpart = integers_of(s, wk + "part", nw, wk + "particle");
    all_below(wpart, std::int64_t{8}, wk + "part", "mesh contact part");
    all_finite(doubles_of(s, wk + "part_normal", nw * D, wk + "particle"), wk + "part_normal", 1.5);
    std::vector<std::array<std::int64_t, 3>> touching(nw);
    for (std::size_t k = 0; k < nw; ++k) {
      if (wid[k] != id[static_cast<std::size_t>(wp[k])])
        refuse_entry(wk + "id", fmt::format("entry {} is not particle {}'s id", k, wp[k]));
      touching[k] = {wid[k], ww[k], wpart[k]};
    }
    std::sort(touching.begin(), touching.end());
    if (std::adjacent_find(touching.begin(), touching.end()) != touching.end())
      refuse_entry(wk + "particle", "lists a particle and wall twice");
    // Records of the size the layout entry (checked above) says.
    struct Histories {
      std::string prefix, counted_by;
      std::size_t count;
    };
    for (const Histories& h : {Histories{pk, pk + "i", np}, Histories{wk, wk + "particle", nw}}) {
      const auto each = static_cast<std::size_t>(s.i(h.prefix + "layout")[1]);
      const std::string key = h.prefix + "history";
      if (s.b(key).size() != h.count * each)
        refuse_entry(key, fmt::format("has {} bytes, expected {} contacts of {} bytes (from '{}')",
                                      s.b(key).size(), h.count, each, h.counted_by));
    }
    for (const auto& [key, count] : {std::pair{pk + "track", np}, std::pair{wk + "track", nw}})
      if (!s.b(key).empty() && s.b(key).size() != count * sizeof(ContactTrack<D>))
        refuse_entry(key, fmt::format("has {} bytes, expected none or {} contacts of {} bytes",
                                      s.b(key).size(), count, sizeof(ContactTrack<D>)));
    slot_ranges.emplace_back(static_cast<std::size_t>(s.i(pk + "layout")[0]), np);
    slot_ranges.emplace_back(static_cast<std::size_t>(s.i(wk + "layout")[0]), nw);
  });
  std::sort(slot_ranges.begin(), slot_ranges.end());
  for (std::size_t k = 1; k < slot_ranges.size(); ++k)
    if (slot_ranges[k - 1].second > 0 &&
        slot_ranges[k - 1].first + slot_ranges[k - 1].second > slot_ranges[k].first &&
        slot_ranges[k].second > 0)
      refuse_entry("layout", "the contact lists' slot ranges overlap");
  const std::string& hook_names = s.t("hooks");  // one line each
  const auto hook_count =
      static_cast<std::size_t>(std::count(hook_names.begin(), hook_names.end(), '\n'));
  const auto& origin = s.d("hooks.origin_time");
  const auto& periods = s.i("hooks.periods");
  if (origin.size() != hook_count)
    refuse_entry("hooks.origin_time",
                 fmt::format("has {} values for {} hooks", origin.size(), hook_count));
  if (periods.size() != hook_count)
    refuse_entry("hooks.periods",
                 fmt::format("has {} values for {} hooks", periods.size(), hook_count));
  for (std::size_t k = 0; k < origin.size(); ++k)
    if (!std::isfinite(origin[k]))
      refuse_entry("hooks.origin_time", fmt::format("value {} is {}", k, origin[k]));
  // The clock's origin: time = origin time + (step - origin step) dt, with the dt
  // the origin was taken with (0 before the first step).
  const auto& clock = s.d("clock");
  const auto& clock_step = s.i("clock");
  if (clock.size() != 2) refuse_entry("clock", fmt::format("has {} doubles, not 2", clock.size()));
  if (clock_step.size() != 1)
    refuse_entry("clock", fmt::format("has {} integers, not 1", clock_step.size()));
  {
    const auto& md = s.d("meta");
    const double time = md[0], dt = md[1];
    const std::int64_t step = s.i("meta")[2];
    if (!std::isfinite(clock[0]) || !(clock[0] >= 0) || !(clock[0] <= time) ||
        !std::isfinite(clock[1]) || !(clock[1] >= 0) || clock_step[0] < 0 || clock_step[0] > step)
      refuse_entry("clock",
                   fmt::format("origin t = {} s at step {} (step {} s) does not lie before "
                               "the state's t = {} s, step {}",
                               clock[0], clock_step[0], clock[1], time, step));
    const double on_clock = clock[0] + static_cast<double>(step - clock_step[0]) * clock[1];
    if (clock[1] == dt && step > clock_step[0] &&
        !(std::abs(on_clock - time) <= 1e-6 * dt + 1e-12 * std::abs(time)))
      refuse_entry("clock", fmt::format("gives t = {} s at step {}, the state says {} s", on_clock,
                                        step, time));
  }
  const auto& guards = s.i("guards");
  if (guards.size() != 2)
    refuse_entry("guards", fmt::format("has {} values, not 2", guards.size()));
  for (std::size_t k = 0; k < 2; ++k)
    if (guards[k] != 0 && guards[k] != 1)
      refuse_entry("guards", fmt::format("value {} is {}, not 0 or 1", k, guards[k]));
  (void)s.t("time_step.governing_pair");
  // Absent in checkpoints written before the warning existed: none was given.
  if (s.integers.count("guards.wall_overlap_warned")) {
    const auto& warned = s.i("guards.wall_overlap_warned");
    if (warned.size() != 1 || (warned[0] != 0 && warned[0] != 1))
      refuse_entry(
          "guards.wall_overlap_warned",
          fmt::format("must be one value, 0 or 1 (has {} values{})", warned.size(),
                      warned.empty() ? std::string() : fmt::format(", the first {}", warned[0])));
  }
  // Absent when the grace was for all particles, or off (and in checkpoints written
  // before it was kept: those restart with the grace for all).
  if (s.integers.count("guards.placed_ids")) {
    const auto& placed = s.i("guards.placed_ids");
    if (guards[0] != 1)
      refuse_entry("guards.placed_ids", "is present, but the grace (guards, value 0) is off");
    for (std::size_t k = 0; k < placed.size(); ++k)
      if (placed[k] < 0 || (k > 0 && placed[k] <= placed[k - 1]))
        refuse_entry("guards.placed_ids",
                     fmt::format("value {} is {}: the ids must be non-negative and increasing", k,
                                 placed[k]));
  }
  // Absent in checkpoints of older builds (the rule's kind is then found anew).
  if (s.integers.count("time_step.per_contact")) {
    const auto& kind = s.i("time_step.per_contact");
    if (kind.size() != 1 || (kind[0] != 0 && kind[0] != 1))
      refuse_entry("time_step.per_contact", "must be one value, 0 or 1");
  }
  // Present only in a state a failed run left, at the step it failed at.
  if (s.integers.count("guards.failed_at_step")) {
    const auto& failed = s.i("guards.failed_at_step");
    if (failed.size() != 1 || failed[0] != meta[2])
      refuse_entry("guards.failed_at_step",
                   fmt::format("must be one value, the state's step {}", meta[2]));
  }
  // The last step's results (save_last_step): absent in checkpoints of older builds,
  // else all there. Counts of contacts fit the lists' 32-bit indices; a step notes and
  // rebalances each model's pair list at most once.
  if (s.integers.count("last_step.tallies") || s.doubles.count("last_step.max_overlap_ratio") ||
      s.doubles.count("last_step.wall_reactions")) {
    const std::string key = "last_step.tallies";
    const auto& tallies = integers_of(s, key, 7);
    const std::int64_t counts = std::int64_t{1} << 32,
                       models = static_cast<std::int64_t>(contact_model_count);
    for (std::size_t k = 0; k < tallies.size(); ++k)
      if (tallies[k] < 0 || (k < 5 ? tallies[k] > counts : tallies[k] / models > meta[2]))
        refuse_entry(key,
                     fmt::format("value {} is {}: not a count this state can have", k, tallies[k]));
    if (tallies[1] > tallies[0] || tallies[3] > tallies[2])
      refuse_entry(key, "counts more batched contacts than contacts");
    const double ratio = doubles_of(s, "last_step.max_overlap_ratio", 1)[0];
    if (!(std::isfinite(ratio) && ratio >= 0))
      refuse_entry("last_step.max_overlap_ratio",
                   fmt::format("is {}: must be finite and >= 0", number_text(ratio)));
    all_finite(doubles_of(s, "last_step.wall_reactions", (D + 1) * wall_count, "walls"),
               "last_step.wall_reactions", std::numeric_limits<double>::max());
  }
  if (s.integers.count("last_step.contacts") || s.doubles.count("last_step.contacts") ||
      s.texts.count("last_step.contact_models")) {
    const std::string key = "last_step.contacts";
    const auto& ids = s.i(key);
    if (ids.size() % 4 != 0)
      refuse_entry(key, fmt::format("has {} integers, not 4 per contact", ids.size()));
    const std::size_t count = ids.size() / 4;
    all_finite(doubles_of(s, key, 8 * count, key + " (integers)"), key,
               std::numeric_limits<double>::max());
    const auto models = s.lines("last_step.contact_models");
    const auto catalogue = contact_model_catalogue();
    for (const auto& m : models)
      if (std::none_of(catalogue.begin(), catalogue.end(),
                       [&](const ContactModelInfo& c) { return c.name == m; }))
        refuse_entry("last_step.contact_models", fmt::format("names '{}', no contact model", m));
    auto live = [&](std::int64_t id) {
      return id >= 0 && id < next_id && index_of_id[static_cast<std::size_t>(id)] >= 0;
    };
    for (std::size_t k = 0; k < count; ++k) {
      const std::int64_t* c = &ids[4 * k];
      const bool pair = c[1] >= 0 && c[2] == -1,
                 wall = c[1] == -1 && c[2] >= 0 && c[2] < static_cast<std::int64_t>(wall_count);
      if (!live(c[0]) || !(pair ? live(c[1]) : wall) || c[3] < 0 ||
          c[3] >= static_cast<std::int64_t>(models.size()))
        refuse_entry(key, fmt::format("contact {} ({}, {}, wall {}, model {}) names no particle, "
                                      "wall or model of this checkpoint",
                                      k, c[0], c[1], c[2], c[3]));
    }
  }
  // Absent in checkpoints written before the setting existed: those ran without it.
  if (s.integers.count("canonical_order")) {
    const auto& canonical = s.i("canonical_order");
    if (canonical.size() != 1 || (canonical[0] != 0 && canonical[0] != 1))
      refuse_entry("canonical_order",
                   fmt::format("must be one value, 0 or 1 (has {} values{})", canonical.size(),
                               canonical.empty() ? std::string()
                                                 : fmt::format(", the first {}", canonical[0])));
  }
}
template void check_state<2>(const StateBlob&, std::size_t, std::size_t);
template void check_state<3>(const StateBlob&, std::size_t, std::size_t);

}  // namespace granule
