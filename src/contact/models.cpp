#include "contact/models.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"

namespace granule {

std::vector<ContactModelInfo> contact_model_catalogue() {
  std::vector<ContactModelInfo> out;
  for_each_model([&](auto index) {
    using M = ContactModelAt<decltype(index)::value>;
    out.push_back({M::name, M::doc, M::parameters(), M::adhesive, has_force_batch<M>::value});
  });
  return out;
}

int contact_model_id(const std::string& name) {
  auto catalogue = contact_model_catalogue();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < catalogue.size(); ++i) {
    if (catalogue[i].name == name) return static_cast<int>(i);
    names.push_back(catalogue[i].name);
  }
  std::string hint = nearest_name(name, names);
  throw InputError(fmt::format("unknown contact model '{}'{} (known: {})", name,
                               hint.empty() ? "" : fmt::format(", did you mean '{}'?", hint),
                               fmt::join(names, ", ")));
}

}  // namespace granule
