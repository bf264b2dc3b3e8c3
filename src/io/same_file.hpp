// Whether two paths name one file, for refusing to write one file as two
// things (a run's output over its checkpoint, its scene or the checkpoint it
// continues).
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace granule::io {

// The same file where both exist (links too); otherwise the same absolute
// path once '.', '..' and the links of its existing part are resolved.
inline bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  if (a.empty() || b.empty()) return false;
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) {
    const bool same = fs::equivalent(a, b, error);
    if (!error) return same;
  }
  std::error_code error_a, error_b;
  const fs::path path_a = fs::weakly_canonical(fs::absolute(a), error_a);
  const fs::path path_b = fs::weakly_canonical(fs::absolute(b), error_b);
  return !error_a && !error_b && path_a == path_b;
}

// Whether `path` names something that is there and is not a plain file (a
// device, a pipe, a folder): a file written beside and renamed over it would
// replace it (as root, /dev/full).
inline bool names_non_file(const std::string& path) {
  std::error_code error;
  const auto there = std::filesystem::status(path, error);
  return std::filesystem::exists(there) && !std::filesystem::is_regular_file(there);
}

}  // namespace granule::io
