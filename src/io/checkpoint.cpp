#include "io/checkpoint.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "io/h5_handle.hpp"
#include "io/h5_output.hpp"
#include "io/journalled_file.hpp"
#include "io/rank_files.hpp"
#include "io/same_file.hpp"

namespace granule::io {

namespace {

constexpr const char* format_name = "granule-checkpoint-1";

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(fmt::format("checkpoint {}: {}", path, what));
}

[[noreturn]] void fail_h5(const std::string& path, const std::string& what) {
  const std::string detail = hdf5_error_text();
  fail(path, detail.empty() ? what : what + " (" + detail + ")");
}

hid_t check(hid_t id, const std::string& path, const std::string& what) {
  if (id < 0) fail_h5(path, "cannot " + what);
  return id;
}

// Byte arrays past this size (the scene's journal, contact histories) are written in
// deflated chunks: a journal of values a scene read halves (level 1, ~50 MB/s).
constexpr hsize_t compress_bytes_from = hsize_t{1} << 20;

template <typename T>
void write_array(hid_t group, const std::string& name, hid_t file_type, hid_t mem_type,
                 const std::vector<T>& v, const std::string& path) {
  hsize_t n = v.size();
  Handle space(check(H5Screate_simple(1, &n, nullptr), path, "create a dataspace"), H5Sclose);
  Handle dcpl(check(H5Pcreate(H5P_DATASET_CREATE), path, "make a dataset property list"), H5Pclose);
  // Every array with data carries HDF5's Fletcher-32 checksum per chunk: a bit flipped on
  // disk (a bad sector, a file copied in part) is refused at the restart rather than
  // continued from. The checksum wants chunks; an array up to 1 MiB is one.
  // (The checksum is the pipeline's last filter: it covers the bytes on disk.)
  if (n > 0) {
    const hsize_t chunk = std::min<hsize_t>(n, compress_bytes_from / sizeof(T));
    if (H5Pset_chunk(dcpl.get(), 1, &chunk) < 0) fail_h5(path, "cannot chunk " + name);
    if (sizeof(T) == 1 && n >= compress_bytes_from && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0 &&
        H5Pset_deflate(dcpl.get(), 1) < 0)
      fail_h5(path, "cannot set compression for " + name);
    if (H5Pset_fletcher32(dcpl.get()) < 0) fail_h5(path, "cannot set the checksum of " + name);
  }
  Handle d(check(H5Dcreate2(group, name.c_str(), file_type, space.get(), H5P_DEFAULT, dcpl.get(),
                            H5P_DEFAULT),
                 path, "create " + name),
           H5Dclose);
  if (n > 0 && H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    fail_h5(path, "cannot write " + name);
}

void write_string(hid_t loc, const std::string& name, const std::string& value, bool attribute,
                  const std::string& path) {
  Handle type(check(H5Tcopy(H5T_C_S1), path, "make a string type"), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space(check(H5Screate(H5S_SCALAR), path, "create a dataspace"), H5Sclose);
  const char* p = value.c_str();
  if (attribute) {
    Handle a(check(H5Acreate2(loc, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                   path, "create attribute " + name),
             H5Aclose);
    if (H5Awrite(a.get(), type.get(), &p) < 0) fail_h5(path, "cannot write attribute " + name);
  } else {
    Handle d(check(H5Dcreate2(loc, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   path, "create " + name),
             H5Dclose);
    if (H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0)
      fail_h5(path, "cannot write " + name);
  }
}

std::string read_string(hid_t loc, const std::string& name, bool attribute,
                        const std::string& path) {
  Handle type(check(H5Tcopy(H5T_C_S1), path, "make a string type"), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  char* p = nullptr;
  if (attribute) {
    Handle a(check(H5Aopen(loc, name.c_str(), H5P_DEFAULT), path, "open attribute " + name),
             H5Aclose);
    if (H5Aread(a.get(), type.get(), &p) < 0) fail(path, "cannot read attribute " + name);
  } else {
    Handle d(check(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), path, "open " + name), H5Dclose);
    if (H5Dread(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0)
      fail(path, "cannot read " + name);
  }
  std::string out = p ? p : "";
  H5free_memory(p);
  return out;
}

template <typename T>
std::vector<T> read_array(hid_t group, const std::string& name, hid_t mem_type,
                          const std::string& path) {
  Handle d(check(H5Dopen2(group, name.c_str(), H5P_DEFAULT), path, "open " + name), H5Dclose);
  Handle space(check(H5Dget_space(d.get()), path, "read " + name), H5Sclose);
  if (H5Sget_simple_extent_ndims(space.get()) != 1) fail(path, name + " is not a 1-D array");
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space.get(), &n, nullptr);
  std::vector<T> out(n);
  if (n > 0 && H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(path, "cannot read " + name + " (damaged: its checksum does not match, or unreadable)");
  return out;
}

std::vector<std::string> member_names(hid_t group, const std::string& path) {
  H5G_info_t info;
  if (H5Gget_info(group, &info) < 0) fail(path, "cannot list a group");
  std::vector<std::string> names;
  for (hsize_t k = 0; k < info.nlinks; ++k) {
    ssize_t len =
        H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, nullptr, 0, H5P_DEFAULT);
    if (len < 0) fail(path, "cannot list a group");
    std::string name(static_cast<std::size_t>(len), '\0');
    H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, k, name.data(), name.size() + 1,
                       H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

}  // namespace

namespace {
// The four groups of a StateBlob (doubles, integers, bytes, texts) under `root`.
void write_blob(hid_t root, const StateBlob& s, const std::string& path) {
  auto group = [&](const char* name) {
    return Handle(check(H5Gcreate2(root, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), path,
                        std::string("create ") + name),
                  H5Gclose);
  };
  {
    Handle g = group("doubles");
    for (const auto& [k, v] : s.doubles)
      write_array(g.get(), k, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v, path);
  }
  {
    Handle g = group("integers");
    for (const auto& [k, v] : s.integers)
      write_array(g.get(), k, H5T_STD_I64LE, H5T_NATIVE_INT64, v, path);
  }
  {
    Handle g = group("bytes");
    for (const auto& [k, v] : s.bytes)
      write_array(g.get(), k, H5T_STD_U8LE, H5T_NATIVE_UINT8, v, path);
  }
  {
    Handle g = group("texts");
    for (const auto& [k, v] : s.texts) write_string(g.get(), k, v, false, path);
  }
}

StateBlob read_blob(hid_t root, const std::string& path) {
  StateBlob s;
  auto open = [&](const char* name) {
    return Handle(check(H5Gopen2(root, name, H5P_DEFAULT), path, std::string("open ") + name),
                  H5Gclose);
  };
  {
    Handle g = open("doubles");
    for (const auto& k : member_names(g.get(), path))
      s.doubles[k] = read_array<double>(g.get(), k, H5T_NATIVE_DOUBLE, path);
  }
  {
    Handle g = open("integers");
    for (const auto& k : member_names(g.get(), path))
      s.integers[k] = read_array<std::int64_t>(g.get(), k, H5T_NATIVE_INT64, path);
  }
  {
    Handle g = open("bytes");
    for (const auto& k : member_names(g.get(), path))
      s.bytes[k] = read_array<std::uint8_t>(g.get(), k, H5T_NATIVE_UINT8, path);
  }
  {
    Handle g = open("texts");
    for (const auto& k : member_names(g.get(), path))
      s.texts[k] = read_string(g.get(), k, false, path);
  }
  return s;
}

// Through the driver the run's output is open with (io/journalled_file.hpp), so that
// HDF5 sees a file this process has open already as that file (and refuses to write
// to the open output: its locking setting differs).
hid_t open_existing(const std::string& file, unsigned flags) {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (fapl.get() < 0) return H5I_INVALID_HID;
  use_journalled_driver(fapl.get());
  return H5Fopen(file.c_str(), flags, fapl.get());
}

void write_file(const std::string& path, const std::string& tmp, const StateBlob& s,
                const std::map<std::string, std::string>& attributes) {
  Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (file.get() < 0) fail_h5(path, fmt::format("cannot create {} (is the folder writable?)", tmp));
  {
    Handle root(check(H5Gcreate2(file.get(), "/checkpoint", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      path, "create /checkpoint"),
                H5Gclose);
    write_string(root.get(), "format", format_name, true, path);
    for (const auto& [k, v] : attributes) write_string(root.get(), k, v, true, path);
    write_blob(root.get(), s, path);
  }
  if (H5Fflush(file.get(), H5F_SCOPE_GLOBAL) < 0) fail_h5(path, "cannot flush " + tmp);
  // Closing writes what HDF5 still holds (metadata): a close that fails leaves a file
  // that must not replace the last good checkpoint.
  const herr_t closed = H5Fclose(file.get());
  file.release();
  if (closed < 0) fail_h5(path, "cannot close " + tmp);
}
}  // namespace

void write_checkpoint(const std::string& named, const StateBlob& s,
                      const std::map<std::string, std::string>& attributes) {
  silence_hdf5();
  const std::string path = writable_path(named);
  const std::string tmp = path + ".tmp";
  std::error_code ec;
  if (names_non_file(path))
    fail(path,
         "exists and is not a plain file (a device, a pipe or a folder): a checkpoint "
         "replaces its file, so name a file");
  try {
    write_file(path, tmp, s, attributes);
  } catch (const std::runtime_error& e) {
    // The half-written file goes (it would fill the disk further and could be taken for a
    // checkpoint); the last good one stays where it was.
    std::filesystem::remove(tmp, ec);
    const bool kept = std::filesystem::exists(path, ec);
    const std::string full = disk_full_note(path, e.what());
    throw std::runtime_error(
        fmt::format("{}{}; {}", e.what(), full.empty() ? "" : "; " + full,
                    kept ? fmt::format("the previous checkpoint {} is kept", path)
                         : std::string("no checkpoint was written")));
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(path, fmt::format("cannot rename {} into place: {}", tmp, ec.message()));
  }
}

StateBlob read_checkpoint(const std::string& path, std::map<std::string, std::string>* attributes) {
  silence_hdf5();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  Handle file(open_existing(readable_path(path), H5F_ACC_RDONLY), H5Fclose);
  if (file.get() < 0) fail(path, "not an HDF5 file");
  if (H5Lexists(file.get(), "/checkpoint", H5P_DEFAULT) <= 0)
    fail(path, "not a Granule checkpoint (no /checkpoint group)");
  Handle root(check(H5Gopen2(file.get(), "/checkpoint", H5P_DEFAULT), path, "open /checkpoint"),
              H5Gclose);
  if (H5Aexists(root.get(), "format") <= 0 ||
      read_string(root.get(), "format", true, path) != format_name)
    fail(path, fmt::format("not a {} file", format_name));
  if (attributes) {
    H5O_info_t info;
    if (H5Oget_info2(root.get(), &info, H5O_INFO_NUM_ATTRS) < 0)
      fail(path, "cannot read attributes");
    for (hsize_t k = 0; k < info.num_attrs; ++k) {
      char name[256] = {0};
      if (H5Aget_name_by_idx(root.get(), ".", H5_INDEX_NAME, H5_ITER_INC, k, name, sizeof name,
                             H5P_DEFAULT) < 0)
        fail(path, "cannot read attributes");
      (*attributes)[name] = read_string(root.get(), name, true, path);
    }
  }
  return read_blob(root.get(), path);
}

std::string read_checkpoint_text(const std::string& path, const std::string& key) {
  silence_hdf5();
  Handle file(open_existing(readable_path(path), H5F_ACC_RDONLY), H5Fclose);
  if (file.get() < 0) fail(path, "not an HDF5 file");
  const std::string name = "/checkpoint/texts/" + key;
  if (H5Lexists(file.get(), "/checkpoint", H5P_DEFAULT) <= 0 ||
      H5Lexists(file.get(), "/checkpoint/texts", H5P_DEFAULT) <= 0 ||
      H5Lexists(file.get(), name.c_str(), H5P_DEFAULT) <= 0)
    fail(path, "has no " + name);
  return read_string(file.get(), name, false, path);
}

void add_state_group(const std::string& path, const std::string& group, const StateBlob& s) {
  silence_hdf5();
  Handle file(open_existing(writable_path(path, true), H5F_ACC_RDWR), H5Fclose);
  if (file.get() < 0)
    fail_h5(path, "cannot open for writing (not an HDF5 file, or still open by its run?)");
  if (H5Lexists(file.get(), group.c_str(), H5P_DEFAULT) > 0) fail(path, group + " exists already");
  {
    Handle root(check(H5Gcreate2(file.get(), group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      path, "create " + group),
                H5Gclose);
    write_string(root.get(), "format", format_name, true, path);
    write_blob(root.get(), s, path);
  }
  const herr_t closed = H5Fclose(file.get());
  file.release();
  if (closed < 0) fail_h5(path, "cannot close after writing " + group);
}

bool has_state_group(const std::string& path, const std::string& group) {
  silence_hdf5();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  Handle file(open_existing(readable_path(path), H5F_ACC_RDONLY), H5Fclose);
  if (file.get() < 0) fail(path, "not an HDF5 file");
  return H5Lexists(file.get(), group.c_str(), H5P_DEFAULT) > 0;
}

StateBlob read_state_group(const std::string& path, const std::string& group) {
  silence_hdf5();
  Handle file(open_existing(readable_path(path), H5F_ACC_RDONLY), H5Fclose);
  if (file.get() < 0) fail(path, "not an HDF5 file");
  if (H5Lexists(file.get(), group.c_str(), H5P_DEFAULT) <= 0) fail(path, "has no " + group);
  Handle root(check(H5Gopen2(file.get(), group.c_str(), H5P_DEFAULT), path, "open " + group),
              H5Gclose);
  if (H5Aexists(root.get(), "format") <= 0 ||
      read_string(root.get(), "format", true, path) != format_name)
    fail(path, fmt::format("{} is not in the {} layout", group, format_name));
  return read_blob(root.get(), path);
}

}  // namespace granule::io
