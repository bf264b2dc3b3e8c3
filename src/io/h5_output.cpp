#include "io/h5_output.hpp"

#include <fmt/format.h>
#include <hdf5.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <utility>

namespace granule::io {

namespace {

// Rows of a series wait in memory until this many are pending or this much wall time has
// passed, so that a run appending every step does not flush the file every step.
constexpr std::size_t series_batch_rows = 1024;
constexpr double series_batch_seconds = 0.5;
// Chunk of an extendible series dataset: 8 KiB, a good size for appending and for reading
// a whole column back.
constexpr hsize_t series_chunk_rows = 1024;

// Owns one hid_t and closes it with the matching H5*close; move-only, so no handle is
// closed twice or leaked when an exception unwinds.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t get() const { return id_; }
  void release() { id_ = H5I_INVALID_HID; }  // forgets the id without closing it
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// The library's own description of the error just raised (innermost first), since our
// messages replace HDF5's automatic stack printing.
herr_t collect_error(unsigned n, const H5E_error2_t* err, void* data) {
  auto* text = static_cast<std::string*>(data);
  if (n == 0 && err && err->desc) *text = err->desc;
  return 0;
}

std::string h5_error_detail() {
  const std::string text = hdf5_error_text();
  return text.empty() ? "HDF5 error" : text;
}

// H5Pset_file_locking exists from 1.10.7 in the 1.10 series and from 1.12.1 after that.
#if (H5_VERS_MAJOR == 1 && H5_VERS_MINOR == 10 && H5_VERS_RELEASE >= 7) || H5_VERSION_GE(1, 12, 1)
#define GRANULE_HAVE_FILE_LOCKING_PLIST 1
#endif

void silence_hdf5() {
  // Users should see our messages, which name the file and object, not HDF5's stack dump.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

std::string iso_time_now() {
  std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buf;
}

std::string join_path(const std::string& group, const std::string& name) {
  return group == "/" ? "/" + name : group + "/" + name;
}

}  // namespace

std::string hdf5_error_text() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_error, &text);
  // A failed write's description carries the call's whole record (time, descriptor,
  // buffer address, over two lines); its first words and the system's message suffice.
  const std::string marker = "error message = '";
  const auto m = text.find(marker);
  if (m != std::string::npos) {
    const auto end = text.find('\'', m + marker.size());
    text = text.substr(0, text.find(':')) + ": " +
           text.substr(m + marker.size(), end == std::string::npos ? end : end - m - marker.size());
  }
  return text;
}

void keep_hdf5_files_at_exit() {
  H5dont_atexit();
}

std::string disk_full_note(const std::string& path, const std::string& detail) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs {};
  const bool measured = statvfs(dir.c_str(), &fs) == 0;
  const double free_bytes = measured ? double(fs.f_bavail) * double(fs.f_frsize) : 0;
  const bool enospc = detail.find("No space left") != std::string::npos ||
                      detail.find("errno = 28") != std::string::npos;
  if (!enospc && !(measured && free_bytes < 1024.0 * 1024.0)) return "";
  return fmt::format("no space left on the disk holding {} ({:.0f} KiB free)", dir.string(),
                     free_bytes / 1024);
}

struct H5Output::Impl {
  struct Series {
    std::vector<std::string> columns;
    std::vector<Handle> datasets;  // one per column, kept open while the file is
    std::vector<double> pending;   // buffered rows, row-major
    hsize_t written = 0;           // rows already in the file
    std::chrono::steady_clock::time_point last_write;
  };

  std::string path;
  Handle file;  // declared first: destroyed last, after every object opened in it
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
  void ensure_space(double bytes, const std::string& what, const std::string& object) {
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    if (dir.empty()) dir = ".";
    struct statvfs fs {};
    if (statvfs(dir.c_str(), &fs) != 0) return;  // cannot tell: let the write find out
    const double free_bytes = double(fs.f_bavail) * double(fs.f_frsize);
    if (free_bytes >= bytes + 65536.0) return;
    health = Health::full;
    failure =
        fmt::format("no space left on the disk holding {} ({:.0f} KiB free, {:.0f} KiB needed)",
                    dir.string(), free_bytes / 1024, (bytes + 65536.0) / 1024);
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
  }

  void write_series(const std::string& group_path, Series& s) {
    const std::size_t ncol = s.columns.size();
    const hsize_t rows = s.pending.size() / ncol;
    s.last_write = std::chrono::steady_clock::now();
    if (rows == 0) return;
    const hsize_t total = s.written + rows;
    ensure_space(double(rows) * double(ncol) * sizeof(double), "write", group_path);
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

  void flush_file() { check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush", "/"); }
};

H5Output::H5Output(const std::string& path) : impl_(std::make_unique<Impl>()) {
  silence_hdf5();
  impl_->path = path;
  if (path.empty()) throw std::runtime_error("cannot create HDF5 output: empty file name");
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (fapl.get() < 0)
    throw std::runtime_error(
        fmt::format("cannot create HDF5 file {}: {}", path, h5_error_detail()));
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
  // No file lock. HDF5's lock would keep readers (h5py, the plotting tools, h5_input in this
  // process) out of a running simulation's file, and it does not protect the file from a
  // second writer either: HDF5 1.10 truncates the file before it finds the lock taken.
  if (H5Pset_file_locking(fapl.get(), 0, 1) < 0)
    throw std::runtime_error(
        fmt::format("cannot create HDF5 file {}: {}", path, h5_error_detail()));
#endif
  hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (f < 0)
    throw std::runtime_error(
        fmt::format("cannot create HDF5 file {}: {}", path, h5_error_detail()));
  impl_->file = Handle(f, H5Fclose);
  impl_->string_attribute("/", "format", "granule-1");
  impl_->string_attribute("/", "created", iso_time_now());
  unsigned major = 0, minor = 0, release = 0;
  H5get_libversion(&major, &minor, &release);
  impl_->string_attribute("/", "hdf5_version", fmt::format("{}.{}.{}", major, minor, release));
  impl_->flush_file();
}

H5Output::~H5Output() {
  Impl& m = *impl_;
  if (m.health == Impl::Health::ok) {
    try {
      m.write_all_series();
      m.flush_file();
    } catch (const std::exception& e) {
      // A destructor must not throw, but losing the last rows silently would hide a full disk.
      std::fprintf(stderr, "granule: warning: %s\n", e.what());
    }
  }
  m.series.clear();  // their datasets close before the file
  if (m.health != Impl::Health::broken && m.file.get() >= 0 && H5Fclose(m.file.get()) >= 0) {
    m.file.release();
    return;
  }
  // A file whose writes failed is not closed: HDF5 would flush its cache into it again
  // (and its close callback crashes on a file whose flush failed). Its descriptor goes
  // with the process; `granule` asks HDF5 not to close such files at exit either
  // (keep_hdf5_files_at_exit).
  m.file.release();
}

const std::string& H5Output::path() const {
  return impl_->path;
}

std::size_t H5Output::snapshot_count() const {
  return impl_->snapshots;
}

void H5Output::write_text(const std::string& dataset_path, const std::string& text) {
  Impl& m = *impl_;
  silence_hdf5();
  const std::string p = m.normalise(dataset_path, "write text");
  m.usable("write text", p);
  if (p == "/") m.fail("write text", p, "the root group cannot be a dataset");
  if (text.find('\0') != std::string::npos)
    m.fail("write text", p, "text contains a NUL character, which HDF5 strings cannot hold");
  if (m.exists(p)) {
    // Replace an earlier text, but never delete a group with everything in it.
    Handle old(m.check(H5Oopen(m.file.get(), p.c_str(), H5P_DEFAULT), "replace", p), H5Oclose);
    if (H5Iget_type(old.get()) != H5I_DATASET)
      m.fail("write text", p, "a group of that name exists");
    old.reset();
    m.check(H5Ldelete(m.file.get(), p.c_str(), H5P_DEFAULT), "replace", p);
  } else {
    m.check_parents_are_groups(p, "create");
  }
  Handle type = Impl::string_type(H5T_VARIABLE);
  Handle space(m.check(H5Screate(H5S_SCALAR), "create", p), H5Sclose);
  Handle lcpl = m.link_create_plist(p);
  Handle d(m.check(H5Dcreate2(m.file.get(), p.c_str(), type.get(), space.get(), lcpl.get(),
                              H5P_DEFAULT, H5P_DEFAULT),
                   "create", p),
           H5Dclose);
  const char* ptr = text.c_str();
  m.check(H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr), "write", p);
}

void H5Output::write_attribute(const std::string& group_path, const std::string& name,
                               double value) {
  Impl& m = *impl_;
  silence_hdf5();
  m.usable("write attribute", group_path + "@" + name);
  const std::string p = m.normalise(group_path, "write attribute");
  if (!std::isfinite(value))
    m.fail("write attribute", p + "@" + name, fmt::format("value {} is not finite", value));
  m.attribute(p, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &value);
}

void H5Output::write_attribute(const std::string& group_path, const std::string& name,
                               std::int64_t value) {
  Impl& m = *impl_;
  silence_hdf5();
  m.usable("write attribute", group_path + "@" + name);
  m.attribute(m.normalise(group_path, "write attribute"), name, H5T_STD_I64LE, H5T_NATIVE_INT64, {},
              &value);
}

void H5Output::write_attribute(const std::string& group_path, const std::string& name,
                               const std::string& value) {
  Impl& m = *impl_;
  silence_hdf5();
  m.usable("write attribute", group_path + "@" + name);
  m.string_attribute(m.normalise(group_path, "write attribute"), name, value);
}

void H5Output::write_attribute(const std::string& group_path, const std::string& name,
                               const std::vector<double>& value) {
  Impl& m = *impl_;
  silence_hdf5();
  m.usable("write attribute", group_path + "@" + name);
  const std::string p = m.normalise(group_path, "write attribute");
  for (std::size_t i = 0; i < value.size(); ++i)
    if (!std::isfinite(value[i]))
      m.fail("write attribute", p + "@" + name,
             fmt::format("element {} is {}, not finite", i, value[i]));
  m.attribute(p, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {value.size()}, value.data());
}

void H5Output::series_declare(const std::string& group_path,
                              const std::vector<std::string>& columns,
                              const std::vector<std::string>& units) {
  Impl& m = *impl_;
  silence_hdf5();
  const std::string p = m.normalise(group_path, "declare series");
  m.usable("declare series", p);
  auto it = m.series.find(p);
  if (it != m.series.end()) {
    if (it->second.columns == columns) return;
    m.fail("declare series", p,
           fmt::format("already declared with columns [{}], now [{}]",
                       fmt::join(it->second.columns, ", "), fmt::join(columns, ", ")));
  }
  if (p == "/" || p == "/snapshots" || p.rfind("/snapshots/", 0) == 0)
    m.fail("declare series", p, "this group is reserved");
  if (columns.empty()) m.fail("declare series", p, "a series needs at least one column");
  if (!units.empty() && units.size() != columns.size())
    m.fail("declare series", p,
           fmt::format("{} units given for {} columns", units.size(), columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    if (name.empty() || name == "." || name.find('/') != std::string::npos ||
        name.find('\0') != std::string::npos)
      m.fail("declare series", p, fmt::format("column name '{}' is not a plain name", name));
    for (std::size_t d = 0; d < c; ++d)
      if (columns[d] == name)
        m.fail("declare series", p, fmt::format("column '{}' appears twice", name));
  }

  Impl::Series s;
  s.columns = columns;
  {
    Handle g = m.group(p);
    const hsize_t zero = 0, unlimited = H5S_UNLIMITED;
    Handle dcpl(m.check(H5Pcreate(H5P_DATASET_CREATE), "declare series", p), H5Pclose);
    m.check(H5Pset_chunk(dcpl.get(), 1, &series_chunk_rows), "declare series", p);
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const std::string full = join_path(p, columns[c]);
      Handle space(m.check(H5Screate_simple(1, &zero, &unlimited), "create", full), H5Sclose);
      Handle lcpl = m.link_create_plist(full);
      s.datasets.emplace_back(m.check(H5Dcreate2(g.get(), columns[c].c_str(), H5T_IEEE_F64LE,
                                                 space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT),
                                      "create", full),
                              H5Dclose);
      if (!units.empty()) m.string_attribute(full, "unit", units[c]);
    }
  }
  // Readers take the column order from here: HDF5 lists links alphabetically.
  m.string_array_attribute(p, "columns", columns);
  s.last_write = std::chrono::steady_clock::now();
  m.series.emplace(p, std::move(s));
}

void H5Output::series_append(const std::string& group_path, const std::vector<double>& row) {
  Impl& m = *impl_;
  silence_hdf5();
  const std::string p = m.normalise(group_path, "append to series");
  m.usable("append to series", p);
  auto it = m.series.find(p);
  if (it == m.series.end()) m.fail("append to series", p, "the series was never declared");
  Impl::Series& s = it->second;
  if (row.size() != s.columns.size())
    m.fail("append to series", p,
           fmt::format("row has {} values but the series has {} columns", row.size(),
                       s.columns.size()));
  for (std::size_t c = 0; c < row.size(); ++c)
    if (!std::isfinite(row[c]))
      m.fail("append to series", join_path(p, s.columns[c]),
             fmt::format("value {} for column '{}' is not finite", row[c], s.columns[c]));
  s.pending.insert(s.pending.end(), row.begin(), row.end());
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - s.last_write).count();
  if (s.pending.size() / s.columns.size() >= series_batch_rows || waited >= series_batch_seconds) {
    m.write_series(p, s);
    m.flush_file();
  }
}

std::string H5Output::write_snapshot(const SnapshotView& v) {
  Impl& m = *impl_;
  silence_hdf5();
  const std::string name = fmt::format("{:06d}", m.snapshots);
  const std::string g = "/snapshots/" + name;
  auto refuse = [&](const std::string& why) { m.fail("write snapshot", g, why); };
  m.usable("write snapshot", g);

  // Check everything before writing anything, so that a refused snapshot leaves no trace.
  if (v.dimension != 2 && v.dimension != 3)
    refuse(fmt::format("dimension must be 2 or 3, got {}", v.dimension));
  if (v.spin_components != 1 && v.spin_components != 3)
    refuse(fmt::format("spin_components must be 1 or 3, got {}", v.spin_components));
  if (!std::isfinite(v.time)) refuse(fmt::format("time {} is not finite", v.time));
  if (v.count > 0) {
    const std::pair<const void*, const char*> arrays[] = {{v.id, "id"},
                                                          {v.radius, "radius"},
                                                          {v.position, "position"},
                                                          {v.velocity, "velocity"},
                                                          {v.spin, "spin"},
                                                          {v.material, "material"},
                                                          {v.fixed, "fixed"}};
    for (const auto& [ptr, what] : arrays)
      if (!ptr) refuse(fmt::format("no {} array for {} particles", what, v.count));
  }
  const std::size_t d = v.dimension, sc = v.spin_components;
  auto check_rows = [&](const double* data, std::size_t width, const char* what) {
    for (std::size_t i = 0; i < v.count; ++i)
      for (std::size_t k = 0; k < width; ++k)
        if (!std::isfinite(data[i * width + k])) {
          std::vector<double> row(data + i * width, data + (i + 1) * width);
          refuse(fmt::format("particle id {} has non-finite {} ({})", v.id[i], what,
                             fmt::join(row, ", ")));
        }
  };
  check_rows(v.radius, 1, "radius");
  check_rows(v.position, d, "position");
  check_rows(v.velocity, d, "velocity");
  check_rows(v.spin, sc, "spin");
  if (!v.material_names.empty())
    for (std::size_t i = 0; i < v.count; ++i)
      if (v.material[i] < 0 || static_cast<std::size_t>(v.material[i]) >= v.material_names.size())
        refuse(fmt::format("particle id {} has material index {}, but there are {} materials",
                           v.id[i], v.material[i], v.material_names.size()));

  // Room for the arrays (and the series rows written with them) before any is written.
  {
    double bytes = double(v.count) * (8 + 8 + 8.0 * double(2 * d + sc) + 4 + 1);
    for (const auto& [name, series] : m.series) bytes += 8.0 * double(series.pending.size());
    m.ensure_space(bytes, "write snapshot", g);
  }
  // Series rows up to this moment belong on disk together with the snapshot.
  m.write_all_series();

  bool created = false;
  try {
    {
      Handle lcpl = m.link_create_plist(g);
      Handle group(
          m.check(H5Gcreate2(m.file.get(), g.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                  "create", g),
          H5Gclose);
      created = true;
      const hsize_t n = v.count;
      const hid_t h = group.get();
      m.dataset(h, "id", g + "/id", H5T_STD_I64LE, H5T_NATIVE_INT64, {n}, v.id);
      m.dataset(h, "radius", g + "/radius", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n}, v.radius);
      m.dataset(h, "position", g + "/position", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, d},
                v.position);
      m.dataset(h, "velocity", g + "/velocity", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, d},
                v.velocity);
      m.dataset(h, "spin", g + "/spin", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, sc}, v.spin);
      m.dataset(h, "material", g + "/material", H5T_STD_I32LE, H5T_NATIVE_INT32, {n}, v.material);
      m.dataset(h, "fixed", g + "/fixed", H5T_STD_U8LE, H5T_NATIVE_UINT8, {n}, v.fixed);
    }
    const std::int64_t dimension = v.dimension;
    m.attribute(g, "step", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &v.step);
    m.attribute(g, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {}, &v.time);
    m.attribute(g, "dimension", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &dimension);
    // The count is written last: readers trust it, so a half-written snapshot is never
    // counted.
    const std::int64_t count = static_cast<std::int64_t>(m.snapshots) + 1;
    m.attribute("/snapshots", "count", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &count);
  } catch (...) {
    if (created) H5Ldelete(m.file.get(), g.c_str(), H5P_DEFAULT);
    throw;
  }
  ++m.snapshots;
  // Written with the first snapshot, and again only if the engine's material list changes
  // (an empty list never replaces a known one).
  if (!m.materials_written || (!v.material_names.empty() && v.material_names != m.material_names)) {
    m.string_array_attribute("/materials", "names", v.material_names);
    m.material_names = v.material_names;
    m.materials_written = true;
  }
  m.flush_file();
  return g;
}

void H5Output::flush() {
  silence_hdf5();
  impl_->usable("flush", impl_->path);
  impl_->write_all_series();
  impl_->flush_file();
}

H5Output::H5Output() : impl_(std::make_unique<Impl>()) {}

std::map<std::string, std::int64_t> H5Output::series_rows() const {
  std::map<std::string, std::int64_t> out;
  for (const auto& [name, s] : impl_->series)
    out[name] = static_cast<std::int64_t>(s.written + s.pending.size() / s.columns.size());
  return out;
}

namespace {
herr_t collect_attribute_name(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}
herr_t collect_link_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}
}  // namespace

std::vector<std::string> H5Output::attribute_names(const std::string& group_path) const {
  silence_hdf5();
  std::vector<std::string> names;
  const std::string p = impl_->normalise(group_path, "read attributes of");
  if (!impl_->exists(p)) return names;
  Handle obj(impl_->check(H5Oopen(impl_->file.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Oclose);
  hsize_t at = 0;
  impl_->check(
      H5Aiterate2(obj.get(), H5_INDEX_NAME, H5_ITER_INC, &at, collect_attribute_name, &names),
      "read attributes of", p);
  return names;
}

std::unique_ptr<H5Output> H5Output::reopen(const std::string& path, std::size_t snapshots,
                                           const std::map<std::string, std::int64_t>& series_rows,
                                           const std::string& attribute_group,
                                           const std::vector<std::string>& attributes) {
  silence_hdf5();
  std::unique_ptr<H5Output> out(new H5Output());
  Impl& m = *out->impl_;
  m.path = path;
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
  if (fapl.get() >= 0) H5Pset_file_locking(fapl.get(), 0, 1);
#endif
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get());
  if (f < 0)
    throw std::runtime_error(
        fmt::format("cannot open {} to continue it: {}", path, h5_error_detail()));
  m.file = Handle(f, H5Fclose);
  // Snapshots written after the mark go; the count readers trust is set back.
  for (std::size_t k = snapshots;; ++k) {
    const std::string g = fmt::format("/snapshots/{:06d}", k);
    if (!m.exists(g)) break;
    m.check(H5Ldelete(m.file.get(), g.c_str(), H5P_DEFAULT), "remove", g);
  }
  if (m.exists("/snapshots")) {
    const std::int64_t count = static_cast<std::int64_t>(snapshots);
    m.attribute("/snapshots", "count", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &count);
  } else if (snapshots > 0) {
    m.fail("continue", "/snapshots",
           fmt::format("the mark has {} snapshots, the file none", snapshots));
  }
  m.snapshots = snapshots;
  // Series: those of the mark cut back to their rows, any later one removed.
  std::function<void(const std::string&)> visit = [&](const std::string& group) {
    std::vector<std::string> names;
    Handle g(m.check(H5Gopen2(m.file.get(), group.c_str(), H5P_DEFAULT), "open", group), H5Gclose);
    hsize_t at = 0;
    m.check(H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, &at, collect_link_name, &names), "list",
            group);
    for (const auto& name : names) {
      const std::string child = join_path(group, name);
      H5O_info_t info;
      if (H5Oget_info_by_name2(m.file.get(), child.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) <
              0 ||
          info.type != H5O_TYPE_GROUP || child == "/snapshots")
        continue;
      Handle c(m.check(H5Gopen2(m.file.get(), child.c_str(), H5P_DEFAULT), "open", child),
               H5Gclose);
      if (H5Aexists(c.get(), "columns") <= 0) {
        visit(child);
        continue;
      }
      auto it = series_rows.find(child);
      if (it == series_rows.end()) {
        c.reset();
        m.check(H5Ldelete(m.file.get(), child.c_str(), H5P_DEFAULT), "remove", child);
        continue;
      }
      // The columns, in declaration order, from the group's attribute.
      Handle a(m.check(H5Aopen(c.get(), "columns", H5P_DEFAULT), "open", child + "@columns"),
               H5Aclose);
      Handle space(m.check(H5Aget_space(a.get()), "read", child + "@columns"), H5Sclose);
      hsize_t n = 0;
      H5Sget_simple_extent_dims(space.get(), &n, nullptr);
      std::vector<char*> raw(n, nullptr);
      Handle t = Impl::string_type(H5T_VARIABLE);
      if (n > 0) m.check(H5Aread(a.get(), t.get(), raw.data()), "read", child + "@columns");
      Impl::Series series;
      for (char* c_name : raw) {
        series.columns.emplace_back(c_name ? c_name : "");
        H5free_memory(c_name);
      }
      const hsize_t rows = static_cast<hsize_t>(it->second);
      for (const auto& column : series.columns) {
        const std::string d = join_path(child, column);
        Handle ds(m.check(H5Dopen2(m.file.get(), d.c_str(), H5P_DEFAULT), "open", d), H5Dclose);
        Handle dspace(m.check(H5Dget_space(ds.get()), "read", d), H5Sclose);
        hsize_t have = 0;
        H5Sget_simple_extent_dims(dspace.get(), &have, nullptr);
        if (have < rows)
          m.fail("continue", d, fmt::format("it has {} rows, the mark {}", have, rows));
        m.check(H5Dset_extent(ds.get(), &rows), "cut back", d);
        series.datasets.push_back(std::move(ds));
      }
      series.written = rows;
      series.last_write = std::chrono::steady_clock::now();
      m.series[child] = std::move(series);
    }
  };
  visit("/");
  for (const auto& [group, rows] : series_rows)
    if (!m.series.count(group)) m.fail("continue", group, "the series is not in the file");
  // Attributes written after the mark (results) go.
  const std::string ag = m.normalise(attribute_group, "continue");
  if (m.exists(ag)) {
    std::vector<std::string> now = out->attribute_names(ag);
    Handle obj(m.check(H5Oopen(m.file.get(), ag.c_str(), H5P_DEFAULT), "open", ag), H5Oclose);
    for (const auto& name : now)
      if (std::find(attributes.begin(), attributes.end(), name) == attributes.end())
        m.check(H5Adelete(obj.get(), name.c_str()), "remove attribute", ag + "@" + name);
  }
  m.materials_written = false;  // written again at the next snapshot
  m.flush_file();
  return out;
}

}  // namespace granule::io
