#include "contact/pair_table.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"

namespace granule {

void PairTable::set(int a, int b, int model, const ParamValues& values,
                    const PairMaterials& materials) {
  if (values_.size() != table_.size()) values_.resize(table_.size());
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    if (I != model) return;
    using M = ContactModelAt<I>;
    auto& vec = std::get<I>(params_);
    typename M::Params p = M::make(values, materials);
    Entry& ab = table_[key(a, b)];
    int slot;
    if (ab.model == model) {
      slot = ab.slot;
      vec[slot] = p;
    } else {
      slot = static_cast<int>(vec.size());
      vec.push_back(p);
    }
    table_[key(a, b)] = {model, slot};
    table_[key(b, a)] = {model, slot};
  });
  values_[key(a, b)] = values;
  values_[key(b, a)] = values;
}

void PairTable::update(int a, int b, const ParamValues& changes, const std::string& context,
                       const PairMaterials& materials) {
  const Entry& e = at(a, b);
  if (e.model < 0)
    throw InputError(fmt::format("{}: no contact law declared for this pair", context));
  // The rolling term is a bucket of its own (rolling.hpp), chosen once, when
  // the law is declared: a run cannot move a pair's contacts to another.
  const bool rolling = e.model >= base_contact_model_count;
  for (const auto& [k, v] : changes)
    if (is_rolling_parameter(k) && !rolling)
      throw InputError(fmt::format(
          "{}: '{}' needs the rolling term, which is chosen when the contact is declared: "
          "give rolling_friction > 0 or twisting_friction > 0 in sim:contact",
          context, k));
  ParamValues merged = values_[key(a, b)];
  for (const auto& [k, v] : changes) merged[k] = v;
  auto catalogue = contact_model_catalogue();
  // Names and ranges first, then what the values mean together.
  ParamValues resolved = resolve_parameters(catalogue[e.model].parameters, merged, context);
  if (rolling && !(resolved.at("rolling_friction") > 0) && !(resolved.at("twisting_friction") > 0))
    throw InputError(fmt::format(
        "{}: rolling_friction = {} and twisting_friction = {} would remove the rolling term the "
        "contact was declared with; one of them must stay > 0 during a run",
        context, resolved.at("rolling_friction"), resolved.at("twisting_friction")));
  try {  // the law's own checks of its values (M::make), named by the pair
    set(a, b, e.model, resolved, materials);
  } catch (const InputError& error) {
    throw InputError(fmt::format("{}: {}", context, error.what()));
  }
}

ParamValues PairTable::values_in_effect(int a, int b,
                                        const std::vector<Material>& materials) const {
  ParamValues v = values(a, b);
  if (auto it = v.find("surface_energy"); it != v.end())
    it->second = ThorntonJkr::surface_energy_in(v, {materials.at(a), materials.at(b)});
  return v;
}

}  // namespace granule
