// "Did you mean": the nearest known name to a misspelt one, for every error
// that names a parameter, model, diagnostic, material or wall. One function
// for C++ and Lua (lua/granule/checks.lua calls it through granule.nearest_name).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace granule {

// Edits between two strings: Levenshtein's, with two neighbouring letters swapped
// ("rmp" for "rpm") one edit (optimal string alignment). As given: nearest_name
// lowers their case.
std::size_t edit_distance(const std::string& a, const std::string& b);

// The closest name in `candidates` to `name`, case-insensitively (edit distance at most
// max(3, |name| / 3)), or "" if none is that close.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace granule
