// Bindings for agglomerate work (dissertation chapter 7). The loops over
// contacts and the cluster labelling are C++ (src/analysis/breakage.hpp); Lua
// sees one table per call.
#include "lua/wrap_agglomerate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <unordered_set>
#include <vector>

#include "analysis/breakage.hpp"
#include "core/errors.hpp"
#include "io/case_record.hpp"
#include "io/checkpoint.hpp"
#include "io/contact_histories.hpp"
#include "io/h5_input.hpp"
#include "lua/lua_util.hpp"

namespace granule::lua {

namespace {

using analysis::Bond;

std::int64_t whole_number(double v, const std::string& what) {
  if (!(std::floor(v) == v) || std::abs(v) > 9e15)
    throw InputError(fmt::format("{} must be a whole number, got {}", what, v));
  return static_cast<std::int64_t>(v);
}

// The particles a call is about: `particles = {ids}`, `material = "name"`, or
// (neither) every particle in the simulation.
std::vector<std::int64_t> selected_particles(TableReader& t, const SimulationBase& sim) {
  const bool by_ids = t.has("particles"), by_material = t.has("material");
  if (by_ids && by_material)
    throw InputError(fmt::format("{}: give 'particles' or 'material', not both", t.context()));
  std::vector<std::int64_t> ids;
  if (by_ids) {
    for (double v : t.numbers("particles")) {
      const std::int64_t id = whole_number(v, t.context() + ": a particle id");
      if (!sim.has_particle(id))
        throw InputError(fmt::format("{}: 'particles' names particle {}, which does not exist",
                                     t.context(), id));
      ids.push_back(id);
    }
    // A particle named twice would be scaled twice, counted twice: a slip, refused.
    std::vector<std::int64_t> sorted = ids;
    std::sort(sorted.begin(), sorted.end());
    if (auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end())
      throw InputError(fmt::format("{}: 'particles' lists particle {} twice", t.context(), *twice));
  } else if (by_material) {
    const int m = sim.material_id(t.string("material"));
    for (std::int64_t id : sim.particle_ids())
      if (sim.material_of(id) == m) ids.push_back(id);
  } else {
    ids = sim.particle_ids();
  }
  return ids;
}

// The contacts between two of `ids` that the last step saw, as normalised bonds.
// A JKR contact pulled into tension (negative overlap) is still a bond until
// it separates (thornton_jkr.hpp).
std::vector<Bond> current_bonds(const SimulationBase& sim, const std::vector<std::int64_t>& ids) {
  const std::unordered_set<std::int64_t> in(ids.begin(), ids.end());
  std::vector<Bond> out;
  for (const ContactRecord& c : sim.contacts())
    if (c.id_b >= 0 && in.count(c.id_a) && in.count(c.id_b)) out.push_back({c.id_a, c.id_b});
  return analysis::normalized_bonds(std::move(out));
}

std::vector<double> masses_of(const SimulationBase& sim, const std::vector<std::int64_t>& ids) {
  std::vector<double> m;
  m.reserve(ids.size());
  for (std::int64_t id : ids) m.push_back(sim.mass(id));
  return m;
}

// { {a, b}, ... } at the field `key` of table t.
std::vector<Bond> read_bonds(lua_State* L, TableReader& t, const char* key) {
  if (!t.push_table(key))
    throw InputError(
        fmt::format("{}: '{}' is required (a list of {{a, b}} pairs, as sim:bonds "
                    "returns)",
                    t.context(), key));
  std::vector<Bond> bonds;
  const auto n = static_cast<lua_Integer>(lua_rawlen(L, -1));
  bonds.reserve(static_cast<std::size_t>(n));
  for (lua_Integer k = 1; k <= n; ++k) {
    lua_rawgeti(L, -1, k);
    const std::string where = fmt::format("{}: '{}'[{}]", t.context(), key, k);
    if (!lua_istable(L, -1)) {
      lua_pop(L, 2);
      throw InputError(where + " must be a pair {a, b} of particle ids");
    }
    std::int64_t pair[2];
    for (int e = 0; e < 2; ++e) {
      lua_rawgeti(L, -1, e + 1);
      const bool number = lua_isnumber(L, -1);
      const double v = number ? lua_tonumber(L, -1) : 0;
      lua_pop(L, 1);
      if (!number) {
        lua_pop(L, 2);
        throw InputError(where + " must be a pair {a, b} of particle ids");
      }
      pair[e] = whole_number(v, where);
    }
    lua_pop(L, 1);
    bonds.push_back({pair[0], pair[1]});
  }
  lua_pop(L, 1);
  try {
    return analysis::normalized_bonds(std::move(bonds));
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: '{}': {}", t.context(), key, e.what()));
  }
}

void set_integer(lua_State* L, const char* key, std::int64_t v) {
  lua_pushinteger(L, v);
  lua_setfield(L, -2, key);
}
void set_number(lua_State* L, const char* key, double v) {
  lua_pushnumber(L, v);
  lua_setfield(L, -2, key);
}

// Leaves { [id] = label (1 = heaviest) } on the stack.
void push_labels(lua_State* L, const analysis::Fragments& f) {
  lua_createtable(L, 0, static_cast<int>(f.ids.size()));
  for (std::size_t k = 0; k < f.ids.size(); ++k) {
    lua_pushinteger(L, f.label[k] + 1);
    lua_rawseti(L, -2, f.ids[k]);
  }
}

// Where a prepared agglomerate's file keeps its contact histories.
constexpr const char* histories_group = "/contact_histories";

}  // namespace

int load_particles(lua_State* L, SimulationBase& sim) {
  const int d = sim.dimension();
  TableReader t(L, 2, "load_particles");
  const std::string file = t.string("file");
  const long index = static_cast<long>(t.integer("snapshot", -1));
  std::map<std::string, std::string> rename;
  if (t.push_table("material_map")) {
    lua_pushnil(L);
    while (lua_next(L, -2) != 0) {
      if (lua_type(L, -2) != LUA_TSTRING || lua_type(L, -1) != LUA_TSTRING) {
        lua_pop(L, 3);
        throw InputError(
            "load_particles: 'material_map' must map saved material names to names in this "
            "scene, e.g. { alumina = \"primary\" }");
      }
      rename[lua_tostring(L, -2)] = lua_tostring(L, -1);
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  const Triple offset = t.vector("offset", d, {0, 0, 0});
  const Triple added_velocity = t.vector("velocity", d, {0, 0, 0});
  const bool histories_asked = t.has("histories");
  const bool histories_wanted = t.boolean("histories", true);
  t.finish();

  const io::SnapshotData s = io::read_snapshot(file, index);
  // Histories belong to one instant: they are used only with the snapshot of
  // the step they were saved at.
  bool use_histories = false;
  StateBlob saved_histories;
  if (histories_wanted && io::has_state_group(file, histories_group)) {
    saved_histories = io::read_state_group(file, histories_group);
    const auto& meta = saved_histories.i("meta");
    use_histories = meta.size() == 2 && meta[1] == s.step;
    if (!use_histories && histories_asked)
      throw InputError(fmt::format(
          "load_particles: {} holds contact histories of step {}, its snapshot {} is of step {}; "
          "load that snapshot or give histories = false",
          file, meta.size() == 2 ? meta[1] : -1, index, s.step));
  } else if (histories_wanted && histories_asked) {
    throw InputError(fmt::format(
        "load_particles: histories = true, but {} holds no contact histories ({}; written by "
        "sim:save_contact_histories)",
        file, histories_group));
  }
  if (s.dimension != d)
    throw InputError(fmt::format("load_particles: {} holds a {}D snapshot, this scene is {}D", file,
                                 s.dimension, d));
  for (const auto& entry : rename) {
    bool known = false;
    for (const auto& n : s.material_names) known = known || n == entry.first;
    if (!known)
      throw InputError(fmt::format(
          "load_particles: material_map names '{}', which {} does not use (its materials: {})",
          entry.first, file, fmt::join(s.material_names, ", ")));
  }
  // Saved material index -> this scene's material id, resolved on first use.
  std::vector<int> scene_material(s.material_names.size(), -1);
  auto material_for = [&](std::int32_t saved) {
    if (saved < 0 || static_cast<std::size_t>(saved) >= s.material_names.size())
      throw InputError(fmt::format(
          "load_particles: {} has a particle of material index {} but names {} materials", file,
          saved, s.material_names.size()));
    int& m = scene_material[static_cast<std::size_t>(saved)];
    if (m < 0) {
      const std::string& saved_name = s.material_names[static_cast<std::size_t>(saved)];
      auto it = rename.find(saved_name);
      const std::string& name = it == rename.end() ? saved_name : it->second;
      try {
        m = sim.material_id(name);
      } catch (const InputError& e) {
        throw InputError(fmt::format(
            "load_particles: the saved material '{}' needs a material in this scene: {}; "
            "declare it or map it with material_map = {{ {} = \"...\" }}",
            saved_name, e.what(), saved_name));
      }
      // Another density or elasticity gives the loaded particles other masses and
      // their saved overlaps other forces: not the saved state (a prepared
      // agglomerate out of balance). Said, not refused: a packing may be reused so.
      if (static_cast<std::size_t>(saved) < s.material_properties.size()) {
        const auto& was = s.material_properties[static_cast<std::size_t>(saved)];
        const Material& now = sim.materials()[static_cast<std::size_t>(m)];
        const double is[] = {now.density, now.young, now.poisson};
        bool differs = false;
        for (int k = 0; k < 3; ++k)
          differs = differs || (std::isfinite(was[k]) &&
                                std::abs(was[k] - is[k]) > 1e-12 * std::max(std::abs(was[k]), 1.0));
        if (differs)
          sim.warn(fmt::format(
              "load_particles: {} saved '{}' with density {:g} kg/m^3, young {:g} Pa, poisson "
              "{:g}; loaded as '{}' with density {:g}, young {:g}, poisson {:g}: the particles' "
              "masses, or the forces of laws that take young and poisson, are not the saved "
              "state's",
              file, saved_name, was[0], was[1], was[2], name, is[0], is[1], is[2]));
      }
    }
    return m;
  };

  // In the order of the saved ids: the new ids then keep the order of every
  // pair, and with it the sign of its history (the force on the lower id).
  std::vector<std::size_t> order(s.id.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return s.id[x] < s.id[y]; });
  std::vector<std::int64_t> ids;
  ids.reserve(s.id.size());
  std::map<std::int64_t, std::int64_t> renamed;
  const int sc = s.spin_components;
  for (std::size_t i : order) {
    ParticleSpec p;
    p.fixed = s.fixed[i] != 0;
    // A fixed particle keeps its saved motion (at rest, or prescribed): the added
    // velocity moves the free ones, as a thrown agglomerate, not its fixed base.
    for (int k = 0; k < d; ++k) {
      p.position[k] = s.position[i * d + k] + offset[k];
      p.velocity[k] = s.velocity[i * d + k] + (p.fixed ? 0.0 : added_velocity[k]);
    }
    if (sc == 1)
      p.spin = {0, 0, s.spin[i]};
    else
      p.spin = {s.spin[i * 3], s.spin[i * 3 + 1], s.spin[i * 3 + 2]};
    if (d == 2) p.spin[0] = p.spin[1] = 0;
    p.radius = s.radius[i];
    p.material = material_for(s.material[i]);
    ids.push_back(sim.add_particle(p));
    renamed[s.id[i]] = ids.back();
  }
  std::size_t seeded = 0;
  if (use_histories) {
    // Through the engine's own state: the histories join its pair lists keyed
    // by id pair, and its next list rebuild gives each to its contact.
    const std::string wound = sim.wound_legacy_rolling_springs(saved_histories);
    if (!wound.empty())
      throw InputError(fmt::format(
          "load_particles: {} holds '{}' rolling springs wound as torques, as builds before "
          "this one saved them; this build holds them as M / sqrt(k_r) and cannot convert "
          "them: save the histories again with this build, or load with histories = false",
          file, wound));
    sim.prepare();
    StateBlob state = sim.save_state();
    seeded = io::seed_pair_histories(state, saved_histories, renamed, file);
    sim.load_state(state);
  }
  lua_createtable(L, static_cast<int>(ids.size()), 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    lua_pushinteger(L, ids[k]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_pushinteger(L, static_cast<lua_Integer>(seeded));
  // The numbers the run that wrote the file reported (sim:result): a test reads
  // there the law its agglomerate was prepared with.
  const std::map<std::string, double> results = io::read_results(file);
  lua_createtable(L, 0, static_cast<int>(results.size()));
  for (const auto& [name, value] : results) {
    lua_pushnumber(L, value);
    lua_setfield(L, -2, name.c_str());
  }
  return 3;
}

int save_contact_histories(lua_State* L, SimulationBase& sim) {
  TableReader t(L, 2, "save_contact_histories");
  const std::string file = t.string("file");
  const std::vector<std::int64_t> ids = selected_particles(t, sim);
  t.finish();
  const StateBlob part = io::pair_histories_of(sim.save_state(), ids);
  io::add_state_group(file, histories_group, part);
  std::size_t count = 0;
  for (const auto& [key, values] : part.integers)
    if (key.size() > 5 && key.compare(key.size() - 5, 5, ".id_i") == 0) count += values.size();
  lua_pushinteger(L, static_cast<lua_Integer>(count));
  return 1;
}

int bonds(lua_State* L, SimulationBase& sim) {
  if (lua_isnoneornil(L, 2)) lua_newtable(L), lua_replace(L, 2);
  TableReader t(L, 2, "bonds");
  const std::vector<std::int64_t> ids = selected_particles(t, sim);
  t.finish();
  const std::vector<Bond> list = current_bonds(sim, ids);
  lua_createtable(L, static_cast<int>(list.size()), 0);
  for (std::size_t k = 0; k < list.size(); ++k) {
    lua_createtable(L, 2, 0);
    lua_pushinteger(L, list[k].a);
    lua_rawseti(L, -2, 1);
    lua_pushinteger(L, list[k].b);
    lua_rawseti(L, -2, 2);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  return 1;
}

int fragments(lua_State* L, SimulationBase& sim) {
  if (lua_isnoneornil(L, 2)) lua_newtable(L), lua_replace(L, 2);
  TableReader t(L, 2, "fragments");
  const std::vector<std::int64_t> ids = selected_particles(t, sim);
  t.finish();
  const analysis::Fragments f =
      analysis::find_fragments(ids, masses_of(sim, ids), current_bonds(sim, ids));
  lua_newtable(L);
  set_integer(L, "count", static_cast<std::int64_t>(f.count()));
  push_labels(L, f);
  lua_setfield(L, -2, "labels");
  lua_createtable(L, static_cast<int>(f.count()), 0);
  for (std::size_t k = 0; k < f.count(); ++k) {
    lua_pushnumber(L, f.mass[k]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "masses");
  lua_createtable(L, static_cast<int>(f.count()), 0);
  for (std::size_t k = 0; k < f.count(); ++k) {
    lua_pushinteger(L, f.members[k]);
    lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
  }
  lua_setfield(L, -2, "members");
  return 1;
}

int breakage(lua_State* L, SimulationBase& sim) {
  TableReader t(L, 2, "breakage");
  std::vector<Bond> initial = read_bonds(L, t, "initial_bonds");
  // An id the scene never handed out is a slip (a list from another scene, a
  // typo), not a particle removed since: it would count as a broken bond.
  for (std::size_t k = 0; k < initial.size(); ++k)
    for (const std::int64_t id : {initial[k].a, initial[k].b})
      if (id < 0 || id >= sim.ids_handed_out())
        throw InputError(fmt::format(
            "breakage: 'initial_bonds'[{}] names particle {}, which this scene never had ({})",
            k + 1, id,
            sim.ids_handed_out() > 0
                ? fmt::format("its ids run from 0 to {}", sim.ids_handed_out() - 1)
                : std::string("it has had no particles")));
  const std::vector<std::int64_t> ids = selected_particles(t, sim);
  // A bond to a particle outside the selection (another material's, still in the
  // scene) is no bond of the selection's, and could never be found again among
  // its contacts: left out, as the parallel bonds' count leaves it. One to a
  // particle since removed counts, broken.
  {
    std::unordered_set<std::int64_t> selected(ids.begin(), ids.end());
    auto outside = [&](std::int64_t id) { return !selected.count(id) && sim.has_particle(id); };
    initial.erase(std::remove_if(initial.begin(), initial.end(),
                                 [&](const Bond& b) { return outside(b.a) || outside(b.b); }),
                  initial.end());
  }
  const std::vector<double> masses = masses_of(sim, ids);
  double present = 0;
  for (double m : masses) present += m;
  const double initial_mass = t.number("initial_mass", present);
  analysis::FragmentClasses classes;
  classes.large = t.number("large", classes.large);
  classes.debris = t.number("debris", classes.debris);
  classes.fines = t.number("fines", classes.fines);
  const bool labels = t.boolean("labels", false);
  const std::string graph = t.string("graph", "contacts");
  const double initial_count = t.number("initial_count", static_cast<double>(ids.size()));
  t.finish();
  if (graph != "contacts" && graph != "surviving_bonds" && graph != "parallel_bonds")
    throw InputError(fmt::format(
        "breakage: 'graph' must be \"contacts\" (fragments = clusters of the contact graph, 7.4), "
        "\"surviving_bonds\" (of the initial bonds still in contact) or \"parallel_bonds\" (of "
        "the intact parallel bonds, sim:bond), got \"{}\"",
        graph));
  if (!(initial_mass > 0))
    throw InputError(
        fmt::format("breakage: 'initial_mass' must be > 0 [kg] (got {}; no particles selected?)",
                    initial_mass));
  const std::vector<Bond> now = current_bonds(sim, ids);
  // The parallel bonds are read here, in C++, not through a Lua list: a scene
  // samples the breakage every few hundred steps, and the records of a few
  // thousand bonds would otherwise cross into Lua and back at each sample.
  std::vector<analysis::ParallelBondRecord> records;
  for (const SimulationBase::BondRecord& r : sim.bond_records())
    records.push_back({r.id_a, r.id_b, r.broken});
  analysis::ParallelBondState parallel;
  try {
    parallel = analysis::parallel_bond_state(ids, records);
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  if (graph == "parallel_bonds" && parallel.made == 0)
    throw InputError(
        "breakage: graph = \"parallel_bonds\" but the particles selected have no parallel bonds "
        "(make them with sim:bond)");
  const analysis::Fragments f = analysis::find_fragments(
      ids, masses,
      graph == "contacts"         ? now
      : graph == "parallel_bonds" ? parallel.intact
                                  : analysis::surviving_bonds(initial, now));
  analysis::BreakageSummary s;
  try {
    s = analysis::summarize_breakage(initial, now, f, initial_mass, classes,
                                     whole_number(initial_count, "breakage: 'initial_count'"));
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  lua_newtable(L);
  set_number(L, "time", sim.time());
  set_integer(L, "initial_bonds", s.initial_bonds);
  set_integer(L, "bonds", s.bonds);
  set_integer(L, "broken_bonds", s.broken_bonds);
  set_integer(L, "new_bonds", s.new_bonds);
  set_number(L, "damage_ratio", s.damage_ratio);
  set_number(L, "initial_mass", s.initial_mass);
  set_number(L, "debris_mass", s.debris_mass);
  set_number(L, "debris_ratio", s.debris_ratio);
  set_number(L, "fines_ratio", s.fines_ratio);
  set_number(L, "largest_fraction", s.largest_fraction);
  set_integer(L, "fragments", s.fragments);
  set_integer(L, "large", s.large);
  set_integer(L, "medium", s.medium);
  set_integer(L, "small", s.small);
  set_integer(L, "fines", s.fines);
  set_integer(L, "singles", s.singles);
  set_integer(L, "initial_count", s.initial_count);
  set_integer(L, "debris_by_size", s.debris_by_size);
  set_integer(L, "bonded_debris", s.bonded_debris);
  set_number(L, "debris_ratio_by_size", s.debris_ratio_by_size);
  set_number(L, "singles_ratio", s.singles_ratio);
  set_number(L, "bonded_debris_ratio", s.bonded_debris_ratio);
  if (!records.empty()) {
    set_integer(L, "parallel_bonds", parallel.made);
    set_integer(L, "parallel_bonds_broken", parallel.broken);
    set_number(L, "parallel_damage_ratio", parallel.damage_ratio);
  }
  if (labels) {
    push_labels(L, f);
    lua_setfield(L, -2, "labels");
    lua_createtable(L, static_cast<int>(f.count()), 0);
    for (std::size_t k = 0; k < f.count(); ++k) {
      lua_pushnumber(L, f.mass[k] / initial_mass);
      lua_rawseti(L, -2, static_cast<lua_Integer>(k + 1));
    }
    lua_setfield(L, -2, "mass_fractions");
  }
  return 1;
}

int scale_velocities(lua_State* L, SimulationBase& sim) {
  TableReader t(L, 2, "scale_velocities");
  const double factor = t.number("factor");
  const double spin_factor = t.number("spin_factor", factor);
  const std::vector<std::int64_t> ids = selected_particles(t, sim);
  t.finish();
  if (!(factor >= 0) || !(spin_factor >= 0))
    throw InputError(
        fmt::format("scale_velocities: 'factor' and 'spin_factor' must be >= 0, got {} and {}",
                    factor, spin_factor));
  for (std::int64_t id : ids) {
    if (sim.is_fixed(id)) continue;
    Triple v = sim.velocity(id), w = sim.spin(id);
    for (int k = 0; k < 3; ++k) v[k] *= factor, w[k] *= spin_factor;
    sim.set_velocity(id, v);
    sim.set_spin(id, w);
  }
  return 0;
}

}  // namespace granule::lua
