#include "io/rank_files.hpp"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
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

void remove_stale_scratch(const std::string& parent, const std::string& prefix) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(parent, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || !entry.is_directory(ec)) continue;
    const std::size_t dash = name.rfind('-');
    if (dash == std::string::npos || dash + 1 >= name.size()) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + dash + 1, &end, 10);
    if (*end != '\0' || pid <= 0) continue;
    // Gone: no such process here (a live one of another user answers EPERM).
    if (kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::filesystem::remove_all(entry.path(), ec);
  }
}

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
