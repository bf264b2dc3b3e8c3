#include "contact/models.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"

namespace granule {

std::vector<ContactModelInfo> contact_model_catalogue() {
  std::vector<ContactModelInfo> out;
  for_each_model([&](auto index) {
    using M = ContactModelAt<decltype(index)::value>;
    out.push_back({M::name, M::doc, M::parameters(), M::adhesive, has_force_batch<M, 3>::value,
                   has_force_batch<M, 2>::value, has_rolling<M>::value});
  });
  return out;
}

int contact_model_id(const std::string& name) {
  auto catalogue = contact_model_catalogue();
  std::vector<std::string> names;
  for (std::size_t i = 0; i < catalogue.size(); ++i) {
    if (catalogue[i].name == name) return static_cast<int>(i);
    if (!catalogue[i].rolling) names.push_back(catalogue[i].name);
  }
  std::string hint = nearest_name(name, names);
  throw InputError(fmt::format("unknown contact model '{}'{} (known: {})", name,
                               hint.empty() ? "" : fmt::format(", did you mean '{}'?", hint),
                               fmt::join(names, ", ")));
}

int choose_contact_model(int model, ParamValues& given) {
  bool any = false;
  for (const auto& entry : given) any |= is_rolling_parameter(entry.first);
  // Frictions given and all of them 0: the plain law, whatever else was said.
  const auto mu_r = given.find("rolling_friction"), mu_t = given.find("twisting_friction");
  const bool rolling_off = mu_r == given.end() || mu_r->second == 0;
  const bool twisting_off = mu_t == given.end() || mu_t->second == 0;
  if ((mu_r != given.end() || mu_t != given.end()) && rolling_off && twisting_off) {
    for (auto it = given.begin(); it != given.end();)
      it = is_rolling_parameter(it->first) ? given.erase(it) : std::next(it);
    return base_contact_model(model);
  }
  return any ? rolling_contact_model(model) : model;
}

}  // namespace granule
