// The contact-model registry: one line per model. Adding a model means one
// header with a Params/History/force triple, one line here, the model's
// required parameters in the property suite (tests/contact/test_model_properties.cpp)
// and a section with its table markers in docs/contact_models.md.
// The engine keeps one pair bucket per model in this list, and loops over
// each bucket with that model's kernel inlined: a scene whose pairs use one
// model never runs another's code.
#pragma once

#include <string>
#include <tuple>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/hertz_mindlin.hpp"
#include "contact/linear_spring_dashpot.hpp"
#include "contact/parameters.hpp"
#include "contact/thornton_elastic.hpp"
#include "contact/thornton_jkr.hpp"
#include "contact/walton_braun.hpp"

namespace granule {

using ContactModels =
    std::tuple<LinearSpringDashpot, WaltonBraun, HertzMindlin, ThorntonElastic, ThorntonJkr>;

constexpr int contact_model_count = std::tuple_size_v<ContactModels>;

struct ContactModelInfo {
  std::string name;
  std::string doc;
  std::vector<ParamSpec> parameters;
  bool adhesive = false;  // its contacts persist into negative overlap (M::reach)
  bool batched = false;   // it offers the batched 3D kernel (contact_batch.hpp)
};

// All registered models, in registry order (index = model id).
std::vector<ContactModelInfo> contact_model_catalogue();

// Model id for a name, or throws InputError listing the known names.
int contact_model_id(const std::string& name);

// Calls f(std::integral_constant<int, I>{}) for each model index.
template <typename F, std::size_t... I>
void for_each_model_index(F&& f, std::index_sequence<I...>) {
  (f(std::integral_constant<int, static_cast<int>(I)>{}), ...);
}
template <typename F>
void for_each_model(F&& f) {
  for_each_model_index(f, std::make_index_sequence<contact_model_count>{});
}

template <int I>
using ContactModelAt = std::tuple_element_t<I, ContactModels>;

}  // namespace granule
