// Error types. Physics code throws these; the Lua layer turns them into Lua
// errors carrying the script's file and line, the CLI into a message and a
// non-zero exit status.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace granule {

// Invalid user input: a parameter out of range, an unknown name, a particle
// placed outside the walls. The message names the parameter.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The run itself went wrong: a NaN, a particle escaping every wall. The message
// names the step, the particle and the contact.
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A number as a message shows it: a NaN as "nan" whatever its sign bit (0/0
// in a script is a NaN with the bit set, which fmt writes as "-nan").
inline std::string number_text(double v) {
  return std::isnan(v) ? "nan" : fmt::format("{}", v);
}

}  // namespace granule
