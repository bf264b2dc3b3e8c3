// The contact-model registry: one line per model. Adding a model means one
// header with a Params/History/force triple, one line here, the model's
// required parameters in the property suite (tests/contact/test_model_properties.cpp)
// and a section with its table markers in docs/contact_models.md.
// The engine keeps one pair bucket per model in this list, and loops over
// each bucket with that model's kernel inlined: a scene whose pairs use one
// model never runs another's code. Each model is registered twice: as itself
// and with the rolling- and twisting-resistance term (rolling.hpp), the second
// chosen for a pair that declares rolling_friction > 0 or twisting_friction > 0
// (choose_contact_model).
#pragma once

#include <string>
#include <tuple>
#include <vector>

#include "contact/contact_batch.hpp"
#include "contact/hertz_mindlin.hpp"
#include "contact/linear_spring_dashpot.hpp"
#include "contact/parameters.hpp"
#include "contact/rolling.hpp"
#include "contact/thornton_elastic.hpp"
#include "contact/thornton_jkr.hpp"
#include "contact/walton_braun.hpp"

namespace granule {

// The names of the rolling variants (their checkpoint and effects labels).
namespace rolling_names {
inline constexpr char linear[] = "linear+rolling";
inline constexpr char walton_braun[] = "walton_braun+rolling";
inline constexpr char hertz_mindlin[] = "hertz_mindlin+rolling";
inline constexpr char thornton_elastic[] = "thornton_elastic+rolling";
inline constexpr char thornton_jkr[] = "thornton_jkr+rolling";
}  // namespace rolling_names

// The models as the user names them, then the same with rolling resistance,
// in the same order: model b's rolling variant is b + base_contact_model_count.
using ContactModels =
    std::tuple<LinearSpringDashpot, WaltonBraun, HertzMindlin, ThorntonElastic, ThorntonJkr,
               WithRolling<LinearSpringDashpot, rolling_names::linear>,
               WithRolling<WaltonBraun, rolling_names::walton_braun>,
               WithRolling<HertzMindlin, rolling_names::hertz_mindlin>,
               WithRolling<ThorntonElastic, rolling_names::thornton_elastic>,
               WithRolling<ThorntonJkr, rolling_names::thornton_jkr>>;

constexpr int contact_model_count = std::tuple_size_v<ContactModels>;
constexpr int base_contact_model_count = contact_model_count / 2;

struct ContactModelInfo {
  std::string name;
  std::string doc;
  std::vector<ParamSpec> parameters;
  bool adhesive = false;    // its contacts persist into negative overlap (M::reach)
  bool batched_3d = false;  // it offers the batched kernel in 3D (contact_batch.hpp)
  bool batched_2d = false;  // and in 2D
  bool rolling = false;     // the rolling variant of base_contact_model(id)
};

// All registered models, in registry order (index = model id).
std::vector<ContactModelInfo> contact_model_catalogue();

// Model id for a name, or throws InputError listing the known names.
int contact_model_id(const std::string& name);

// The model a user named, and its rolling variant.
inline int base_contact_model(int model) {
  return model % base_contact_model_count;
}
inline int rolling_contact_model(int model) {
  return base_contact_model(model) + base_contact_model_count;
}
// The model id that the parameters `given` for `model` choose: its rolling
// variant when they give rolling_friction > 0 or twisting_friction > 0 (or
// another rolling parameter without either, which the variant then refuses),
// the model itself otherwise; frictions given and all 0 (either alone at 0,
// or both at 0) drop the rolling parameters.
int choose_contact_model(int model, ParamValues& given);

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
