// A material's or wall's name becomes an HDF5 group (/materials/<name>,
// /walls/<name>) and a field of the checkpoint's tab-separated lines: it must be
// printable text without '/' (which would nest groups) and not "." or "..".
#pragma once

#include <fmt/format.h>

#include <string>

#include "core/errors.hpp"

namespace granule {

// Throws InputError naming `what` ("material", "wall") when `name` is not plain.
inline void check_plain_name(const std::string& name, const char* what) {
  if (name.empty()) throw InputError(fmt::format("{}: 'name' must not be empty", what));
  for (unsigned char c : name)
    if (c < 0x20 || c == 0x7f || c == '/') {
      std::string shown;  // the name as typed, its control characters escaped
      for (unsigned char d : name)
        shown += d == '\n'                 ? std::string("\\n")
                 : d == '\t'               ? std::string("\\t")
                 : (d < 0x20 || d == 0x7f) ? fmt::format("\\x{:02x}", d)
                                           : std::string(1, static_cast<char>(d));
      throw InputError(fmt::format(
          "{}: name '{}' holds a '/' or a control character (tab, newline): it names an HDF5 "
          "group and a field of the checkpoint; use letters, digits, '_', '-', '.' or spaces",
          what, shown));
    }
  if (name == "." || name == "..")
    throw InputError(fmt::format("{}: name '{}' cannot name an HDF5 group", what, name));
}

}  // namespace granule
