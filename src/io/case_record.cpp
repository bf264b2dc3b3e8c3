#include "io/case_record.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/fnv1a.hpp"
#include "io/h5_handle.hpp"
#include "io/journalled_file.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

namespace {

std::string attribute_name(hid_t location, hsize_t index) {
  ssize_t n =
      H5Aget_name_by_idx(location, ".", H5_INDEX_NAME, H5_ITER_INC, index, nullptr, 0, H5P_DEFAULT);
  if (n < 0) return "";
  std::vector<char> buffer(static_cast<std::size_t>(n) + 1);
  H5Aget_name_by_idx(location, ".", H5_INDEX_NAME, H5_ITER_INC, index, buffer.data(), buffer.size(),
                     H5P_DEFAULT);
  return std::string(buffer.data());
}

// The file without HDF5's lock: the case's writer has exited, but a file on a shared
// filesystem may refuse flock, and a lock left by a killed writer must not block us.
hid_t open_file(const std::string& path, unsigned flags, bool create = false) {
  silence_hdf5();
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
  H5Pset_file_locking(fapl.get(), 0, 1);
#endif
  use_journalled_driver(fapl.get());  // the output's driver: one file, one driver
  if (create) return H5Fcreate(writable_path(path).c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (flags & H5F_ACC_RDWR) return H5Fopen(writable_path(path, true).c_str(), flags, fapl.get());
  return H5Fopen(readable_path(path).c_str(), flags, fapl.get());
}

std::optional<double> read_number(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return std::nullopt;
  Handle a(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.ok()) return std::nullopt;
  Handle type(H5Aget_type(a.get()), H5Tclose);
  H5T_class_t c = H5Tget_class(type.get());
  Handle space(H5Aget_space(a.get()), H5Sclose);
  if ((c != H5T_FLOAT && c != H5T_INTEGER) || H5Sget_simple_extent_npoints(space.get()) != 1)
    return std::nullopt;
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0) return std::nullopt;
  return v;
}

std::optional<std::string> read_string(hid_t object, const std::string& name) {
  if (H5Aexists(object, name.c_str()) <= 0) return std::nullopt;
  Handle a(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose);
  Handle type(H5Aget_type(a.get()), H5Tclose);
  if (!a.ok() || H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    return std::nullopt;
  std::vector<char> buffer(H5Tget_size(type.get()) + 1, '\0');
  Handle memory(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(memory.get(), buffer.size());
  if (H5Aread(a.get(), memory.get(), buffer.data()) < 0) return std::nullopt;
  return std::string(buffer.data());
}

void replace_attribute(hid_t object, const std::string& name, hid_t type, const void* data,
                       const std::string& path) {
  if (H5Aexists(object, name.c_str()) > 0) H5Adelete(object, name.c_str());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle a(H5Acreate2(object, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.ok() || H5Awrite(a.get(), type, data) < 0)
    throw std::runtime_error(fmt::format("cannot write /sweep_case/{} in {}", name, path));
}

void write_string(hid_t object, const std::string& name, const std::string& value,
                  const std::string& path) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  std::string padded = value.empty() ? std::string(1, '\0') : value;
  replace_attribute(object, name, type.get(), padded.data(), path);
}

}  // namespace

std::string source_digest(const std::string& text) {
  Fnv1a h;
  h.add(text.data(), text.size());
  return fmt::format("{:016x}", h.value());
}

std::map<std::string, double> read_results(const std::string& path) {
  std::map<std::string, double> out;
  Handle file(open_file(path, H5F_ACC_RDONLY), H5Fclose);
  if (!file.ok()) throw std::runtime_error(fmt::format("cannot open HDF5 file {}", path));
  if (H5Lexists(file.get(), "results", H5P_DEFAULT) <= 0) return out;
  Handle group(H5Oopen(file.get(), "results", H5P_DEFAULT), H5Oclose);
  if (!group.ok()) throw std::runtime_error(fmt::format("cannot open /results in {}", path));
  H5O_info_t info{};
#if H5_VERSION_GE(1, 12, 0)
  H5Oget_info3(group.get(), &info, H5O_INFO_NUM_ATTRS);
#else
  H5Oget_info2(group.get(), &info, H5O_INFO_NUM_ATTRS);
#endif
  for (hsize_t k = 0; k < info.num_attrs; ++k) {
    std::string name = attribute_name(group.get(), k);
    if (auto v = read_number(group.get(), name)) out[name] = *v;
  }
  return out;
}

std::optional<CaseRecord> read_case_record(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
  Handle file(open_file(path, H5F_ACC_RDONLY), H5Fclose);
  if (!file.ok() || H5Lexists(file.get(), "sweep_case", H5P_DEFAULT) <= 0) return std::nullopt;
  Handle group(H5Gopen2(file.get(), "sweep_case", H5P_DEFAULT), H5Gclose);
  if (!group.ok()) return std::nullopt;
  auto complete = read_number(group.get(), "complete");
  auto key = read_string(group.get(), "case");
  if (!complete || *complete != 1 || !key) return std::nullopt;
  CaseRecord r;
  r.key = *key;
  r.rank = static_cast<int>(read_number(group.get(), "rank").value_or(0));
  r.wall_seconds = read_number(group.get(), "wall_seconds").value_or(0);
  r.finished = read_string(group.get(), "finished").value_or("");
  r.scene_digest = read_string(group.get(), "scene_digest").value_or("");
  return r;
}

void write_case_record(const std::string& path, const CaseRecord& record) {
  std::error_code ec;
  hid_t id =
      std::filesystem::exists(path, ec) ? open_file(path, H5F_ACC_RDWR) : open_file(path, 0, true);
  Handle file(id, H5Fclose);
  if (!file.ok()) throw std::runtime_error(fmt::format("cannot open {} to mark it finished", path));
  Handle group(H5Lexists(file.get(), "sweep_case", H5P_DEFAULT) > 0
                   ? H5Gopen2(file.get(), "sweep_case", H5P_DEFAULT)
                   : H5Gcreate2(file.get(), "sweep_case", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Gclose);
  if (!group.ok()) throw std::runtime_error(fmt::format("cannot make /sweep_case in {}", path));
  // The mark goes last: a record cut short by a crash here is not taken for a finished case.
  if (H5Aexists(group.get(), "complete") > 0) H5Adelete(group.get(), "complete");
  write_string(group.get(), "case", record.key, path);
  std::int64_t rank = record.rank;
  replace_attribute(group.get(), "rank", H5T_NATIVE_INT64, &rank, path);
  replace_attribute(group.get(), "wall_seconds", H5T_NATIVE_DOUBLE, &record.wall_seconds, path);
  write_string(group.get(), "finished", record.finished.empty() ? iso_time_now() : record.finished,
               path);
  write_string(group.get(), "scene_digest", record.scene_digest, path);
  H5Fflush(file.get(), H5F_SCOPE_LOCAL);
  std::int64_t one = 1;
  replace_attribute(group.get(), "complete", H5T_NATIVE_INT64, &one, path);
  if (H5Fflush(file.get(), H5F_SCOPE_LOCAL) < 0)
    throw std::runtime_error(fmt::format("cannot flush {}", path));
}

}  // namespace granule::io
