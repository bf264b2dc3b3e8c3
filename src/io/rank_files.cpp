#include "io/rank_files.hpp"

#include <filesystem>
#include <system_error>

namespace granule::io {

namespace {
std::string& scratch() {
  static std::string folder;
  return folder;
}
}  // namespace

void write_files_into(const std::string& folder) {
  scratch() = folder;
  if (!folder.empty()) std::filesystem::create_directories(folder);
}

void remove_scratch() {
  if (scratch().empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(scratch(), ec);
  scratch().clear();
}

std::string writable_path(const std::string& path, bool keep_content) {
  if (scratch().empty() || path.empty()) return path;
  // One flat name per absolute path: two files of one name in two folders stay two.
  std::string flat = std::filesystem::absolute(path).lexically_normal().string();
  for (char& c : flat)
    if (c == '/') c = '%';
  const std::filesystem::path mapped = std::filesystem::path(scratch()) / flat;
  std::error_code ec;
  if (keep_content && std::filesystem::exists(path, ec) && !std::filesystem::exists(mapped, ec))
    std::filesystem::copy_file(path, mapped, ec);
  return mapped.string();
}

}  // namespace granule::io
