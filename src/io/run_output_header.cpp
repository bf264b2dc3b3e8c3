// RunOutput's header: the scene's provenance (source, parameters and their units,
// gravity and the central field, materials, contact laws, walls, what is simulated),
// written once, at the first output of the run.
#include <fmt/format.h>

#include "contact/models.hpp"
#include "contact/rolling.hpp"
#include "io/run_output.hpp"

namespace granule::io {

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
      for (const auto& [k, v] : table.values(a, b)) {
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
    auto it = settings_.numeric_parameters.find(name);
    if (it != settings_.numeric_parameters.end())
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
  write_new_laws();
  write_new_walls();
  // What is simulated, as attributes a script can test (1/0, and lists joined by ", ").
  {
    const ActiveEffects e = sim_.effects();
    const std::string g = "/scene/effects";
    auto flag = [&](const char* name, bool on) {
      f.write_attribute(g, name, static_cast<std::int64_t>(on ? 1 : 0));
    };
    auto list = [&](const char* name, const std::vector<std::string>& items) {
      std::string joined;
      for (const auto& item : items) joined += (joined.empty() ? "" : ", ") + item;
      f.write_attribute(g, name, joined);
    };
    f.write_attribute(g, "dimension", static_cast<std::int64_t>(e.dimension));
    flag("periodic", e.periodic);
    list("pairs", e.pairs);
    flag("adhesion", e.adhesion);
    list("adhesive_pairs", e.adhesive_pairs);
    flag("friction", e.friction);
    flag("rotation", e.rotation);
    flag("gravity", e.gravity);
    flag("central_field", e.central_field);
    flag("moving_walls", !e.moving_walls.empty());
    list("moving_wall_names", e.moving_walls);
    list("diagnostics", e.diagnostics);
    flag("contacts_recorded", e.contacts_recorded);
    flag("canonical_order", e.canonical_order);
    f.write_attribute(g, "threads", static_cast<std::int64_t>(e.threads));
    f.write_attribute(g, "ranks", static_cast<std::int64_t>(e.ranks));
    f.write_attribute(g, "decomposition", e.decomposition);
  }
  std::string lines;
  for (const auto& l : sim_.describe()) lines += l + "\n";
  f.write_text("/scene/description", lines);
  f.flush();
}

}  // namespace granule::io
