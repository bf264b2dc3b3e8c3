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

#include "io/h5_output_impl.hpp"
#include "io/journalled_file.hpp"
#include "io/output_units.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

void keep_hdf5_files_at_exit() {
  H5dont_atexit();
}

std::string file_too_large_note() {
  if (const std::uint64_t limit = file_size_limit(); limit > 0)
    return fmt::format("the file would pass this process's file size limit ({:.0f} KiB; ulimit -f)",
                       double(limit) / 1024);
  return "the file would pass the largest file its file system holds";
}

std::string disk_full_note(const std::string& path, const std::string& detail) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs {};
  const bool measured = statvfs(dir.c_str(), &fs) == 0;
  const double free_bytes = measured ? double(fs.f_bavail) * double(fs.f_frsize) : 0;
  if (detail.find("File too large") != std::string::npos ||
      detail.find("errno = 27") != std::string::npos)  // EFBIG
    return file_too_large_note();
  const bool enospc = detail.find("No space left") != std::string::npos ||
                      detail.find("errno = 28") != std::string::npos;
  if (!enospc && !(measured && free_bytes < 1024.0 * 1024.0)) return "";
  return fmt::format("no space left on the disk holding {} ({:.0f} KiB free)", dir.string(),
                     free_bytes / 1024);
}

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
  use_journalled_driver(fapl.get());
  impl_->disk_path = writable_path(path);
  hid_t f = H5Fcreate(impl_->disk_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (f < 0)
    throw std::runtime_error(
        fmt::format("cannot create HDF5 file {}: {}", path, h5_error_detail()));
  impl_->file = Handle(f, H5Fclose);
  // A journal left by an earlier file of this name would put this one back wrong.
  // (Removed once the file is ours: one another process writes keeps its own.)
  remove_journal(impl_->disk_path);
  impl_->file_id = new_file_id();
  impl_->string_attribute("/", "format", "granule-1");
  // Which file this is, for a restart continuing it (reopen): another run writing
  // a file of the same name gives it another id.
  const auto id = static_cast<std::int64_t>(impl_->file_id);
  impl_->attribute("/", "file_id", H5T_STD_I64LE, H5T_NATIVE_INT64, {}, &id);
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
    if (m.health == Impl::Health::ok && !m.keep_journal) remove_journal(m.disk_path);
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

bool H5Output::record_failure(const std::string& message) noexcept {
  Impl& m = *impl_;
  silence_hdf5();
  if (m.health == Impl::Health::broken || m.file.get() < 0) return false;
  const bool refused_before = m.health == Impl::Health::full;
  // Refused writes never reached HDF5, so its cache is in step with the file: one
  // more write fits where its room is reserved first (the attribute and its heap,
  // 8 KiB at most, past which the flush wants ensure_space's 64 KiB).
  if (refused_before &&
      reserve_space(m.file.get(), static_cast<std::uint64_t>(message.size()) + 65536 + 8192) != 0)
    return false;
  m.health = Impl::Health::ok;
  try {
    m.string_attribute("/", "failure", message);
    m.flush_file();
  } catch (const std::exception&) {
    // HDF5's cache may now hold what the file lacks: the file is not flushed or
    // closed again (the destructor), so it keeps what it held before.
    if (refused_before) m.health = Impl::Health::broken;
    return false;
  }
  if (refused_before) m.health = Impl::Health::full;
  return true;
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
      // "units" on every column (given, else the table's, else "": not known); "unit" as before.
      const std::string unit = units.empty() ? unit_of(columns[c]) : units[c];
      m.string_attribute(full, "units", unit);
      if (!units.empty()) m.string_attribute(full, "unit", units[c]);
    }
  }
  // Readers take the column order from here: HDF5 lists links alphabetically.
  m.string_array_attribute(p, "columns", columns);
  s.last_write = std::chrono::steady_clock::now();
  m.series.emplace(p, std::move(s));
}

bool H5Output::set_series_units(const std::string& group_path,
                                const std::vector<std::string>& units) {
  Impl& m = *impl_;
  silence_hdf5();
  const std::string p = m.normalise(group_path, "set series units");
  auto it = m.series.find(p);
  if (it == m.series.end()) return false;
  const auto& columns = it->second.columns;
  // One unit for a series of several columns: the unit of each but `time` (s).
  if (units.size() == 1 && columns.size() > 1) {
    for (const auto& c : columns)
      m.string_attribute(join_path(p, c), "units", c == "time" ? std::string("s") : units[0]);
    return true;
  }
  if (columns.size() != units.size()) return false;
  for (std::size_t c = 0; c < units.size(); ++c)
    m.string_attribute(join_path(p, columns[c]), "units", units[c]);
  return true;
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
  if (v.force) check_rows(v.force, d, "force");
  if (v.torque) check_rows(v.torque, sc, "torque");
  if (!v.material_names.empty())
    for (std::size_t i = 0; i < v.count; ++i)
      if (v.material[i] < 0 || static_cast<std::size_t>(v.material[i]) >= v.material_names.size())
        refuse(fmt::format("particle id {} has material index {}, but there are {} materials",
                           v.id[i], v.material[i], v.material_names.size()));

  // Room for the arrays (and the series rows written with them) before any is written.
  {
    double bytes = double(v.count) * (8 + 8 + 8.0 * double(2 * d + sc) + 4 + 1) +
                   (v.force ? 8.0 * double(v.count) * double(d + sc) : 0) +
                   8.0 * double(v.contacts) * double(4 + 2 * d) + 17.0 * double(v.bonds);
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
      if (v.force)
        m.dataset(h, "force", g + "/force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, d}, v.force);
      if (v.torque)
        m.dataset(h, "torque", g + "/torque", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {n, sc}, v.torque);
    }
    if (v.with_contacts) {
      const std::string c = g + "/contacts";
      Handle group = m.group(c);
      const hsize_t k = v.contacts;
      const hid_t h = group.get();
      m.dataset(h, "i", c + "/i", H5T_STD_I64LE, H5T_NATIVE_INT64, {k}, v.contact_i);
      m.dataset(h, "j", c + "/j", H5T_STD_I64LE, H5T_NATIVE_INT64, {k}, v.contact_j);
      m.dataset(h, "wall", c + "/wall", H5T_STD_I32LE, H5T_NATIVE_INT32, {k}, v.contact_wall);
      m.dataset(h, "overlap", c + "/overlap", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {k},
                v.contact_overlap);
      m.dataset(h, "normal_force", c + "/normal_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {k},
                v.contact_normal_force);
      m.dataset(h, "tangential_force", c + "/tangential_force", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE,
                {k, d}, v.contact_tangential_force);
      m.dataset(h, "normal", c + "/normal", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {k, d},
                v.contact_normal);
    }
    if (v.bond_a) {
      const std::string b = g + "/bonds";
      Handle group = m.group(b);
      const hsize_t k = v.bonds;
      const hid_t h = group.get();
      m.dataset(h, "a", b + "/a", H5T_STD_I64LE, H5T_NATIVE_INT64, {k}, v.bond_a);
      m.dataset(h, "b", b + "/b", H5T_STD_I64LE, H5T_NATIVE_INT64, {k}, v.bond_b);
      m.dataset(h, "broken", b + "/broken", H5T_STD_U8LE, H5T_NATIVE_UINT8, {k}, v.bond_broken);
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

std::uint64_t H5Output::mark() {
  flush();
  try {
    mark_journal(impl_->file.get(), impl_->file_id);
  } catch (const std::exception& e) {
    const std::string full = disk_full_note(impl_->disk_path, e.what());
    impl_->fail("mark for a restart", "/", full.empty() ? e.what() : full + " (" + e.what() + ")");
  }
  return impl_->file_id;
}

void H5Output::forget_journal(const std::string& path) {
  remove_journal(path);
}

bool H5Output::restore(const std::string& original, const std::string& target,
                       std::uint64_t file_id) {
  return restore_journal(original, target, file_id);
}

}  // namespace granule::io
