#include "contact/rolling.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"

namespace granule {

double rolling_model_code(const std::string& name, const std::string& context) {
  if (name == "epsd") return rolling_model::epsd;
  if (name == "constant") return rolling_model::constant;
  throw InputError(
      fmt::format("{}: rolling_model '{}' is not known (known: epsd, constant)", context, name));
}

const char* rolling_model_name(double code) {
  return code == rolling_model::constant ? "constant" : "epsd";
}

std::vector<ParamSpec> rolling_parameters() {
  return {
      {"rolling_friction", "-", 0, 0, unbounded, true,
       "rolling friction coefficient mu_r: the rolling torque is at most mu_r R* N (N + 2Nc "
       "for thornton_jkr; 0: no rolling resistance; with twisting_friction 0 too, the plain "
       "law)"},
      {"twisting_friction", "-", 0, 0, unbounded, true,
       "twisting friction coefficient mu_t (3D): the torque about the contact normal is at most "
       "mu_t R* N (N + 2Nc for thornton_jkr; 0: no twisting resistance)"},
      {"rolling_model", "-", rolling_model::epsd, 0, 1, true,
       "a name: \"epsd\" (default), elastic-plastic spring-dashpot, Ai et al. 2011 type C; "
       "\"constant\", constant torques mu_r R* N against the rolling and mu_t R* N against the "
       "twisting"},
      {"rolling_damping", "-", 0, 0, unbounded, true,
       "viscous damping ratio eta_r of the epsd rolling and twisting dashpots (0: springs only)"},
  };
}

bool is_rolling_parameter(const std::string& name) {
  for (const ParamSpec& p : rolling_parameters())
    if (name == p.name) return true;
  return false;
}

}  // namespace granule
