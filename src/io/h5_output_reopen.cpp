// Continuing a file H5Output wrote (a restarted run): cut back to a checkpoint's
// mark, then written on.
#include <algorithm>
#include <functional>

#include "io/h5_output.hpp"
#include "io/h5_output_impl.hpp"
#include "io/journalled_file.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

H5Output::H5Output() : impl_(std::make_unique<Impl>()) {}

std::map<std::string, std::int64_t> H5Output::series_rows() const {
  std::map<std::string, std::int64_t> out;
  for (const auto& [name, s] : impl_->series)
    out[name] = static_cast<std::int64_t>(s.written + s.pending.size() / s.columns.size());
  return out;
}

std::vector<std::string> H5Output::series_columns(const std::string& group_path) const {
  auto it = impl_->series.find(group_path);
  return it == impl_->series.end() ? std::vector<std::string>{} : it->second.columns;
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

std::vector<std::string> H5Output::top_level_names() const {
  std::vector<std::string> names;
  Handle g(impl_->check(H5Gopen2(impl_->file.get(), "/", H5P_DEFAULT), "open", "/"), H5Gclose);
  hsize_t at = 0;
  impl_->check(H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, &at, collect_link_name, &names),
               "list", "/");
  return names;
}

std::unique_ptr<H5Output> H5Output::reopen(const std::string& path, std::size_t snapshots,
                                           const std::map<std::string, std::int64_t>& series_rows,
                                           const Kept& kept, std::uint64_t file_id) {
  silence_hdf5();
  // Which file it is, read before anything is made of it and before the journalled
  // open below (which starts a journal under the checkpoint's id: one left beside
  // another run's file would refuse that run's own restart later).
  if (file_id != 0) {
    std::int64_t on_file = 0;
    Handle plain(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
    if (plain.get() >= 0) H5Pset_file_locking(plain.get(), 0, 1);
#endif
    use_journalled_driver(plain.get());  // no journal: only read
    const std::string disk = writable_path(path, true);
    const hid_t r = H5Fopen(disk.c_str(), H5F_ACC_RDONLY, plain.get());
    if (r < 0)
      throw std::runtime_error(
          fmt::format("cannot open {} to continue it: {}", path, h5_error_detail()));
    Handle read_only(r, H5Fclose);
    if (H5Aexists_by_name(r, "/", "file_id", H5P_DEFAULT) > 0) {
      Handle a(H5Aopen_by_name(r, "/", "file_id", H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      if (a.get() < 0 || H5Aread(a.get(), H5T_NATIVE_INT64, &on_file) < 0) on_file = 0;
    }
    if (on_file != static_cast<std::int64_t>(file_id))
      throw OutputOfAnotherRun(fmt::format(
          "cannot continue {}: it is not the file the checkpoint's run wrote (its file_id is {}, "
          "the checkpoint's {})",
          path, on_file, file_id));
  }
  std::unique_ptr<H5Output> out(new H5Output());
  Impl& m = *out->impl_;
  m.path = path;
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
  if (fapl.get() >= 0) H5Pset_file_locking(fapl.get(), 0, 1);
#endif
  // Journalled from the open on, before HDF5 writes a byte: a kill while the file is
  // cut back puts it back as it is now. (Kept until the cut is done: closing a file
  // cut half-way leaves what its journal can undo.)
  m.file_id = file_id != 0 ? file_id : new_file_id();
  use_journalled_driver(fapl.get(), m.file_id);
  m.keep_journal = true;
  m.disk_path = writable_path(path, true);
  hid_t f = H5Fopen(m.disk_path.c_str(), H5F_ACC_RDWR, fapl.get());
  if (f < 0)
    throw std::runtime_error(
        fmt::format("cannot open {} to continue it: {}", path, h5_error_detail()));
  m.file = Handle(f, H5Fclose);
  // Objects and root attributes written after the mark go (a run that went on past it
  // and saved contact histories, or failed).
  for (const auto& name : out->top_level_names())
    if (std::find(kept.top_level.begin(), kept.top_level.end(), name) == kept.top_level.end()) {
      const std::string g = "/" + name;
      m.check(H5Ldelete(m.file.get(), g.c_str(), H5P_DEFAULT), "remove", g);
    }
  {
    Handle root(m.check(H5Oopen(m.file.get(), "/", H5P_DEFAULT), "open", "/"), H5Oclose);
    for (const auto& name : out->attribute_names("/"))
      if (std::find(kept.root_attributes.begin(), kept.root_attributes.end(), name) ==
          kept.root_attributes.end())
        m.check(H5Adelete(root.get(), name.c_str()), "remove attribute", "/@" + name);
  }
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
  const std::string ag = m.normalise(kept.attribute_group, "continue");
  if (m.exists(ag)) {
    std::vector<std::string> now = out->attribute_names(ag);
    Handle obj(m.check(H5Oopen(m.file.get(), ag.c_str(), H5P_DEFAULT), "open", ag), H5Oclose);
    for (const auto& name : now)
      if (std::find(kept.attributes.begin(), kept.attributes.end(), name) == kept.attributes.end())
        m.check(H5Adelete(obj.get(), name.c_str()), "remove attribute", ag + "@" + name);
  }
  m.materials_written = false;  // written again at the next snapshot
  m.flush_file();
  m.keep_journal = false;
  return out;
}

}  // namespace granule::io
