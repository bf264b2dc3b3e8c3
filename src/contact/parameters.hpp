// Parameter descriptors: one list per contact model, used to validate scene
// input, to print help in the REPL and docs, and to record provenance in the
// HDF5 header. A parameter has a name, a unit, a default (NaN = required), a
// valid range and a one-line doc.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/names.hpp"

namespace granule {

struct ParamSpec {
  const char* name;
  const char* unit;
  double default_value;  // NaN: the scene must give it
  double min;
  double max;
  bool min_inclusive;
  const char* doc;
  // 0 or 1 only (allow_tension, calibrate_restitution, shrink_rescale): a value between would read
  // as one of them; a schedule may only jump between them (SimulationBase::add_schedule).
  bool is_switch = false;
};

constexpr double required = std::numeric_limits<double>::quiet_NaN();
constexpr double unbounded = std::numeric_limits<double>::infinity();

using ParamValues = std::map<std::string, double>;

// Checks names against the spec (unknown names are errors that suggest the
// nearest valid one), fills defaults, checks ranges. Throws InputError whose
// message starts with `context` (e.g. "contact 'pmma'-'pmma' (walton_braun)").
// `also_hinted`: names a hint may suggest besides the spec's (a model's rolling
// variant's, when a misspelt rolling parameter chose the model without it).
ParamValues resolve_parameters(const std::vector<ParamSpec>& spec, const ParamValues& given,
                               const std::string& context,
                               const std::vector<ParamSpec>& also_hinted = {});

}  // namespace granule
