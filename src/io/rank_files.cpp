#include "io/rank_files.hpp"

#include <stdlib.h>
#include <unistd.h>

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

namespace {
// One flat name per absolute path: two files of one name in two folders stay two.
std::filesystem::path scratch_copy(const std::string& path) {
  std::string flat = std::filesystem::absolute(path).lexically_normal().string();
  for (char& c : flat)
    if (c == '/') c = '%';
  return std::filesystem::path(scratch()) / flat;
}
}  // namespace

std::string scratch_temporary() {
  if (scratch().empty()) return "";
  std::string name = (std::filesystem::path(scratch()) / "lua_XXXXXX").string();
  const int fd = mkstemp(name.data());
  if (fd < 0) return "";
  close(fd);
  return name;
}

std::string readable_path(const std::string& path) {
  if (scratch().empty() || path.empty()) return path;
  std::error_code ec;
  const std::filesystem::path mapped = scratch_copy(path);
  return std::filesystem::exists(mapped, ec) ? mapped.string() : path;
}

std::string writable_path(const std::string& path, bool keep_content) {
  if (scratch().empty() || path.empty()) return path;
  const std::filesystem::path mapped = scratch_copy(path);
  std::error_code ec;
  if (keep_content && std::filesystem::exists(path, ec) && !std::filesystem::exists(mapped, ec))
    std::filesystem::copy_file(path, mapped, ec);
  return mapped.string();
}

}  // namespace granule::io
