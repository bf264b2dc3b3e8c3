// Inside H5Output (h5_output.cpp, h5_output_reopen.cpp): its handle type, the
// HDF5 helpers and the open file's state. Not for other code.
#pragma once

#include <fmt/format.h>
#include <hdf5.h>
#include <sys/statvfs.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/h5_handle.hpp"
#include "io/h5_output.hpp"
#include "io/journalled_file.hpp"
#include "io/output_units.hpp"

namespace granule::io {

namespace h5_output_detail {

// Rows of a series wait in memory until this many are pending or this much wall time has
// passed, so that a run appending every step does not flush the file every step.
inline constexpr std::size_t series_batch_rows = 1024;
inline constexpr double series_batch_seconds = 0.5;
// Chunk of an extendible series dataset: 8 KiB, a good size for appending and for reading
// a whole column back.
inline constexpr hsize_t series_chunk_rows = 1024;

inline std::string join_path(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

}  // namespace h5_output_detail

using namespace h5_output_detail;

struct H5Output::Impl {
  struct Series {
    std::vector<std::string> columns;
    std::vector<Handle> datasets;  // one per column, kept open while the file is
    std::vector<double> pending;   // buffered rows, row-major
    hsize_t written = 0;           // rows already in the file
    std::chrono::steady_clock::time_point last_write;
  };

  std::string path;
  std::string disk_path;      // where this process writes it (io/rank_files.hpp)
  std::uint64_t file_id = 0;  // names the file to its undo journal (io/journalled_file.hpp)
  bool keep_journal = false;  // even when the file closes cleanly
  Handle file;                // declared first: destroyed last, after every object opened in it
  // After a failed write (a full disk, an I/O error) HDF5's cache no longer matches the
  // file, and flushing or closing it again can write half of its metadata or crash in
  // the library. So the first failure is kept, every later call is refused with it, and
  // the file is left as the last successful flush wrote it. `full`: a write refused
  // before HDF5 was asked (too little space left), so the file was never touched since.
  enum class Health { ok, full, broken } health = Health::ok;
  std::string failure;
  std::map<std::string, Series> series;
  std::size_t snapshots = 0;
  bool materials_written = false;
  std::vector<std::string> material_names;

  [[noreturn]] void fail(const std::string& what, const std::string& object,
                         const std::string& detail) const {
    throw std::runtime_error(fmt::format("cannot {} '{}' in {}: {}", what, object, path, detail));
  }
  [[noreturn]] void fail_h5(const std::string& what, const std::string& object) {
    const std::string detail = h5_error_detail(), full = disk_full_note(path, detail);
    const std::string why = full.empty() ? detail : full + " (" + detail + ")";
    if (!full.empty() || what == "write" || what == "extend" || what == "flush" ||
        what == "write attribute") {
      health = Health::broken;
      failure = why;
    }
    fail(what, object, why);
  }
  hid_t check(hid_t id, const std::string& what, const std::string& object) {
    if (id < 0) fail_h5(what, object);
    return id;
  }
  void check(herr_t status, const std::string& what, const std::string& object) {
    if (status < 0) fail_h5(what, object);
  }
  // Refuses everything once a write has failed (see `health`).
  void usable(const std::string& what, const std::string& object) const {
    if (health != Health::ok)
      fail(what, object,
           fmt::format("an earlier write failed ({}); the file keeps what was written before it",
                       failure));
  }
  // Refuses a write of about `bytes` before HDF5 starts it when the disk lacks the room
  // (with 64 KiB for the metadata written with it): a write that fails halfway through
  // HDF5 leaves its cache out of step with the file.
  // The room is then set aside in the file (reserve_space), so that another writer
  // cannot take it between this check and HDF5's writes.
  void ensure_space(double bytes, const std::string& what, const std::string& object) {
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    if (dir.empty()) dir = ".";
    const double needed = bytes + 65536.0;
    const int reserved = reserve_space(file.get(), static_cast<std::uint64_t>(needed));
    if (reserved == 0) return;
    if (reserved == EFBIG) {  // a file size limit, not the disk
      health = Health::full;
      failure = fmt::format("{}, {:.0f} KiB more needed", file_too_large_note(), needed / 1024);
      fail(what, object, failure);
    }
    struct statvfs fs {};
    const bool measured = statvfs(dir.c_str(), &fs) == 0;
    const double free_bytes = measured ? double(fs.f_bavail) * double(fs.f_frsize) : -1;
    // Without a reservation (the file system has none) the free space is all there is.
    if (reserved < 0 && (!measured || free_bytes >= needed)) return;
    health = Health::full;
    const std::string why = reserved > 0 ? std::string(": ") + std::strerror(reserved) : "";
    failure =
        fmt::format("no space left on the disk holding {} ({}{:.0f} KiB needed{})", dir.string(),
                    measured ? fmt::format("{:.0f} KiB free, ", free_bytes / 1024) : std::string(),
                    needed / 1024, reserved == EDQUOT ? why + " (a disk quota)" : why);
    fail(what, object, failure);
  }

  // "/a/b" from "a/b/", rejecting empty components: HDF5 would read "a//b" as "a/b" but a
  // typo there is more likely a bug in the caller.
  std::string normalise(const std::string& p, const std::string& what) const {
    std::string out = p;
    if (out.empty() || out[0] != '/') out.insert(0, "/");
    while (out.size() > 1 && out.back() == '/') out.pop_back();
    if (out.find("//") != std::string::npos) fail(what, p, "empty path component");
    if (out.find('\0') != std::string::npos) fail(what, p, "NUL character in path");
    return out;
  }

  // Does every component of `p` exist? (H5Lexists needs the parents to exist.)
  bool exists(const std::string& p) {
    if (p == "/") return true;
    std::size_t pos = 0;
    while (pos != std::string::npos) {
      pos = p.find('/', pos + 1);
      std::string prefix = p.substr(0, pos);
      if (H5Lexists(file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    }
    return true;
  }

  // HDF5 reports a dataset in the middle of a path as "message type not found"; say what
  // is wrong instead.
  void check_parents_are_groups(const std::string& p, const std::string& what) {
    for (std::size_t pos = p.find('/', 1); pos != std::string::npos; pos = p.find('/', pos + 1)) {
      const std::string prefix = p.substr(0, pos);
      if (!exists(prefix)) return;
      Handle h(check(H5Oopen(file.get(), prefix.c_str(), H5P_DEFAULT), what, p), H5Oclose);
      if (H5Iget_type(h.get()) != H5I_GROUP)
        fail(what, p, fmt::format("'{}' is not a group", prefix));
    }
  }

  Handle link_create_plist(const std::string& object) {
    Handle lcpl(check(H5Pcreate(H5P_LINK_CREATE), "create", object), H5Pclose);
    check(H5Pset_create_intermediate_group(lcpl.get(), 1), "create", object);
    check(H5Pset_char_encoding(lcpl.get(), H5T_CSET_UTF8), "create", object);
    return lcpl;
  }

  // Opens the object at `p` (any type), creating it as a group with its parents if absent.
  Handle object(const std::string& p) {
    if (exists(p))
      return Handle(check(H5Oopen(file.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Oclose);
    check_parents_are_groups(p, "create");
    Handle lcpl = link_create_plist(p);
    return Handle(
        check(H5Gcreate2(file.get(), p.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), "create", p),
        H5Gclose);
  }

  Handle group(const std::string& p) {
    Handle h = object(p);
    if (H5Iget_type(h.get()) != H5I_GROUP) fail("use as a group", p, "it is not a group");
    return h;
  }

  static Handle string_type(std::size_t size_or_variable) {
    Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
    if (t.get() < 0 || H5Tset_size(t.get(), size_or_variable) < 0 ||
        H5Tset_cset(t.get(), H5T_CSET_UTF8) < 0)
      throw std::runtime_error("cannot make an HDF5 string type: " + h5_error_detail());
    return t;
  }

  // Writes attribute `name` on `where` (replacing one of that name) from `data` of memory
  // type `mem_type`, stored as `file_type` with shape `dims` (empty = scalar).
  void attribute(const std::string& where, const std::string& name, hid_t file_type, hid_t mem_type,
                 const std::vector<hsize_t>& dims, const void* data) {
    const std::string object_name = where + "@" + name;
    if (name.empty() || name.find('\0') != std::string::npos)
      fail("write attribute", object_name, "attribute names must be non-empty plain text");
    Handle obj = object(where);
    htri_t present = H5Aexists(obj.get(), name.c_str());
    check(static_cast<herr_t>(present), "write attribute", object_name);
    if (present > 0) check(H5Adelete(obj.get(), name.c_str()), "replace attribute", object_name);
    Handle space(
        check(dims.empty() ? H5Screate(H5S_SCALAR)
                           : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
              "write attribute", object_name),
        H5Sclose);
    Handle acpl(check(H5Pcreate(H5P_ATTRIBUTE_CREATE), "write attribute", object_name), H5Pclose);
    check(H5Pset_char_encoding(acpl.get(), H5T_CSET_UTF8), "write attribute", object_name);
    Handle attr(
        check(H5Acreate2(obj.get(), name.c_str(), file_type, space.get(), acpl.get(), H5P_DEFAULT),
              "create attribute", object_name),
        H5Aclose);
    bool empty = !dims.empty() && dims[0] == 0;
    if (!empty) check(H5Awrite(attr.get(), mem_type, data), "write attribute", object_name);
  }

  void string_attribute(const std::string& where, const std::string& name,
                        const std::string& value) {
    if (value.find('\0') != std::string::npos)
      fail("write attribute", where + "@" + name,
           "text contains a NUL character, which HDF5 strings cannot hold");
    Handle t = string_type(H5T_VARIABLE);
    const char* p = value.c_str();
    attribute(where, name, t.get(), t.get(), {}, &p);
  }

  void string_array_attribute(const std::string& where, const std::string& name,
                              const std::vector<std::string>& values) {
    std::vector<const char*> ptrs;
    for (const auto& v : values) {
      if (v.find('\0') != std::string::npos)
        fail("write attribute", where + "@" + name,
             "text contains a NUL character, which HDF5 strings cannot hold");
      ptrs.push_back(v.c_str());
    }
    Handle t = string_type(H5T_VARIABLE);
    attribute(where, name, t.get(), t.get(), {values.size()}, ptrs.data());
  }

  // Creates dataset `name` in `group` (at `full` in the file) and writes it whole.
  void dataset(hid_t group, const std::string& name, const std::string& full, hid_t file_type,
               hid_t mem_type, const std::vector<hsize_t>& dims, const void* data) {
    Handle space(check(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                       "create", full),
                 H5Sclose);
    Handle d(check(H5Dcreate2(group, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   "create", full),
             H5Dclose);
    hsize_t total = 1;
    for (hsize_t n : dims) total *= n;
    // An empty snapshot has no buffer to hand HDF5 (its vectors' data() may be null).
    if (total > 0)
      check(H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write", full);
    string_attribute(full, "units", unit_of(name));
  }

  void write_series(const std::string& group_path, Series& s) {
    const std::size_t ncol = s.columns.size();
    const hsize_t rows = s.pending.size() / ncol;
    s.last_write = std::chrono::steady_clock::now();
    if (rows == 0) return;
    const hsize_t total = s.written + rows;
    // Each column's chunks are written whole (series_chunk_rows rows), each new one
    // with an entry in the column's chunk index.
    const hsize_t chunks = (total + series_chunk_rows - 1) / series_chunk_rows -
                           (s.written + series_chunk_rows - 1) / series_chunk_rows;
    ensure_space(
        double(ncol) * (double(chunks) * double(series_chunk_rows) * sizeof(double) + 4096.0),
        "write", group_path);
    // Extend every column before writing any, and forget the rows only when all are
    // written: a failed batch can then be retried whole, leaving the columns equally long.
    for (std::size_t c = 0; c < ncol; ++c)
      check(H5Dset_extent(s.datasets[c].get(), &total), "extend",
            join_path(group_path, s.columns[c]));
    std::vector<double> column(rows);
    Handle memspace(check(H5Screate_simple(1, &rows, nullptr), "write", group_path), H5Sclose);
    for (std::size_t c = 0; c < ncol; ++c) {
      const std::string full = join_path(group_path, s.columns[c]);
      for (hsize_t r = 0; r < rows; ++r) column[r] = s.pending[r * ncol + c];
      Handle filespace(check(H5Dget_space(s.datasets[c].get()), "write", full), H5Sclose);
      check(
          H5Sselect_hyperslab(filespace.get(), H5S_SELECT_SET, &s.written, nullptr, &rows, nullptr),
          "write", full);
      check(H5Dwrite(s.datasets[c].get(), H5T_NATIVE_DOUBLE, memspace.get(), filespace.get(),
                     H5P_DEFAULT, column.data()),
            "write", full);
    }
    s.written = total;
    s.pending.clear();
  }

  void write_all_series() {
    for (auto& [name, s] : series) write_series(name, s);
  }

  // Room for the metadata a flush writes, set aside first (ensure_space).
  void flush_file() {
    ensure_space(0, "flush", "/");
    check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush", "/");
  }
};

}  // namespace granule::io
