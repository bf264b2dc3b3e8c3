// RunOutput's header: the scene's provenance (source, parameters and their units,
// gravity and the central field, materials, contact laws, walls, what is simulated),
// written once, at the first output of the run; /scene/effects grows with each run.
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "contact/models.hpp"
#include "contact/rolling.hpp"
#include "io/effect_fields.hpp"
#include "io/run_output.hpp"

namespace granule::io {

namespace {
void add_new(std::vector<std::string>& list, const std::vector<std::string>& items) {
  for (const auto& item : items)
    if (std::find(list.begin(), list.end(), item) == list.end()) list.push_back(item);
}

}  // namespace

// What the runs written to this file simulated: an effect on in any of them is
// on (a stage that adds friction, gravity, a turning wall or a diagnostic); the
// threads, ranks and decomposition are the last run's. Noted when the header is
// written and at each run's start and end (sim:run); a schedule's values count
// from its declaration (Simulation::effects).
void RunOutput::note_effects() {
  if (!file_) return;
  const ActiveEffects e = sim_.effects();
  for (const auto& [name, flag] : effect_flags())
    effects_seen_.*flag = effects_seen_.*flag || e.*flag;
  for (const auto& [name, list] : effect_lists()) add_new(effects_seen_.*list, e.*list);
  effects_seen_.dimension = e.dimension;
  effects_seen_.threads = e.threads;
  effects_seen_.ranks = e.ranks;
  effects_seen_.decomposition = e.decomposition;
  if (!header_written_) return;
  // As attributes a script can test (1/0, and lists joined by ", ").
  H5Output& f = *file_;
  const std::string g = "/scene/effects";
  f.write_attribute(g, "dimension", static_cast<std::int64_t>(effects_seen_.dimension));
  for (const auto& [name, flag] : effect_flags())
    f.write_attribute(g, name, static_cast<std::int64_t>(effects_seen_.*flag ? 1 : 0));
  f.write_attribute(g, "moving_walls",
                    static_cast<std::int64_t>(effects_seen_.moving_walls.empty() ? 0 : 1));
  for (const auto& [name, list] : effect_lists()) {
    std::string joined;
    for (const auto& item : effects_seen_.*list) joined += (joined.empty() ? "" : ", ") + item;
    f.write_attribute(g, name, joined);
  }
  f.write_attribute(g, "threads", static_cast<std::int64_t>(effects_seen_.threads));
  f.write_attribute(g, "ranks", static_cast<std::int64_t>(effects_seen_.ranks));
  f.write_attribute(g, "decomposition", effects_seen_.decomposition);
}

// Materials and contact laws with their resolved parameters (provenance), each
// as it was when first written: at the header, or at the first output after a
// scene declared it (a wall's material and law made for a later stage).
void RunOutput::write_new_laws() {
  H5Output& f = *file_;
  const auto& mats = sim_.materials();
  const PairTable& table = sim_.pair_table();
  auto catalogue = contact_model_catalogue();
  for (std::size_t k = materials_written_; k < mats.size(); ++k) {
    const Material& m = mats[k];
    std::string g = "/materials/" + m.name;
    f.write_attribute(g, "density", m.density);
    f.write_attribute(g, "young", m.young);
    f.write_attribute(g, "poisson", m.poisson);
    f.write_attribute(g, "surface_energy", m.surface_energy);
  }
  materials_written_ = mats.size();
  for (int a = 0; a < table.material_count(); ++a)
    for (int b = a; b < table.material_count(); ++b) {
      const auto& e = table.at(a, b);
      if (e.model < 0) continue;
      std::string g = fmt::format("/contacts/{}-{}", mats[a].name, mats[b].name);
      if (!laws_written_.insert(g).second) continue;
      f.write_attribute(g, "model", catalogue[e.model].name);
      for (const auto& [k, v] : table.values_in_effect(a, b, mats)) {
        if (k == "rolling_model")
          f.write_attribute(g, k, std::string(rolling_model_name(v)));
        else
          f.write_attribute(g, k, v);
      }
    }
}

void RunOutput::write_header() {
  // Written lazily, at the first output of the run, so that it describes the
  // scene as it runs, whatever order the script declared things in.
  if (header_written_) return;
  header_written_ = true;
  H5Output& f = *file_;
  f.write_attribute("/", "dimension", static_cast<std::int64_t>(sim_.dimension()));
  f.write_attribute("/", "program", std::string("granule"));
  if (!settings_.scene_source.empty()) f.write_text("/scene/source", settings_.scene_source);
  if (!settings_.scene_path.empty()) f.write_attribute("/scene", "path", settings_.scene_path);
  for (const auto& [name, value] : settings_.parameters) {
    auto whole = settings_.integer_parameters.find(name);
    auto it = settings_.numeric_parameters.find(name);
    if (whole != settings_.integer_parameters.end())
      f.write_attribute("/scene/parameters", name, whole->second);
    else if (it != settings_.numeric_parameters.end())
      f.write_attribute("/scene/parameters", name, it->second);
    else
      f.write_attribute("/scene/parameters", name, value);
    // An attribute holds no attributes: each value's unit as it was declared ("" none
    // declared, "-" dimensionless), under the same name in /scene/parameters/units.
    auto u = settings_.parameter_units.find(name);
    f.write_attribute("/scene/parameters/units", name,
                      u == settings_.parameter_units.end() ? std::string() : u->second);
  }
  {
    const auto b = sim_.body_fields();
    const int d = sim_.dimension();
    f.write_attribute("/scene", "gravity",
                      std::vector<double>(b.gravity.begin(), b.gravity.begin() + d));
    f.write_attribute("/scene", "gravity_units", std::string("m/s^2"));
    f.write_attribute("/scene", "central_field", static_cast<std::int64_t>(b.central_on ? 1 : 0));
    if (b.central_on) {
      f.write_attribute("/scene", "central_field_point",
                        std::vector<double>(b.central_point.begin(), b.central_point.begin() + d));
      f.write_attribute("/scene", "central_field_point_units", std::string("m"));
      f.write_attribute("/scene", "central_field_strength", b.central_strength);
      f.write_attribute("/scene", "central_field_strength_units", std::string("m/s^2"));
    }
  }
  if (sim_.is_periodic()) {
    // What a post-processor needs to unwrap positions or measure across the seam.
    const auto& p = sim_.periodicity();
    f.write_attribute("/scene", "periodic_axis", std::string(1, "xyz"[p.axis]));
    f.write_attribute("/scene", "periodic_origin", p.origin);
    f.write_attribute("/scene", "periodic_length", p.length);
    f.write_attribute("/scene", "periodic_units", std::string("m"));
  }
  write_new_laws();
  write_new_walls();
  note_effects();
  std::string lines;
  for (const auto& l : sim_.describe()) lines += l + "\n";
  f.write_text("/scene/description", lines);
  f.flush();
}

}  // namespace granule::io
