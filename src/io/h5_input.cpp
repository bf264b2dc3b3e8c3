#include "io/h5_input.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <filesystem>
#include <limits>
#include <stdexcept>
#include <utility>

#include "io/h5_handle.hpp"
#include "io/journalled_file.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

namespace {

void free_vlen_strings(hid_t type, hid_t space, void* buf) {
#if H5_VERSION_GE(1, 12, 0)
  H5Treclaim(type, space, H5P_DEFAULT, buf);
#else
  H5Dvlen_reclaim(type, space, H5P_DEFAULT, buf);
#endif
}

// An open file plus its path, for messages.
struct File {
  std::string path;
  Handle id;

  explicit File(const std::string& p) : path(p) {
    silence_hdf5();
    std::error_code ec;
    // This rank's copy of a file the scene wrote (io/rank_files.hpp), else the file.
    const std::string file = readable_path(p);
    if (!std::filesystem::exists(file, ec))
      throw std::runtime_error(fmt::format("cannot open {}: no such file", p));
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    if (fapl.get() < 0) fail_h5("open", "/");
#ifdef GRANULE_HAVE_FILE_LOCKING_PLIST
    // H5Output opens its files without a lock so that they can be read while a run goes on,
    // and HDF5 refuses to open one file twice in a process with different locking settings.
    // Files from other writers may hold a lock; reading the flushed part is safe regardless.
    if (H5Pset_file_locking(fapl.get(), 0, 1) < 0) fail_h5("open", "/");
#endif
    // The output's driver: HDF5 knows a file this process writes only through it.
    use_journalled_driver(fapl.get());
    hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, fapl.get());
    if (f < 0)
      throw std::runtime_error(fmt::format("cannot open HDF5 file {}: {}", p, h5_error_detail()));
    id = Handle(f, H5Fclose);
  }

  [[noreturn]] void fail(const std::string& what, const std::string& object,
                         const std::string& detail) const {
    throw std::runtime_error(fmt::format("cannot {} '{}' in {}: {}", what, object, path, detail));
  }
  [[noreturn]] void fail_h5(const std::string& what, const std::string& object) const {
    fail(what, object, h5_error_detail());
  }
  hid_t check(hid_t h, const std::string& what, const std::string& object) const {
    if (h < 0) fail_h5(what, object);
    return h;
  }
  void check(herr_t status, const std::string& what, const std::string& object) const {
    if (status < 0) fail_h5(what, object);
  }

  bool exists(const std::string& p) const {
    if (p == "/") return true;
    std::size_t pos = 0;
    while (pos != std::string::npos) {
      pos = p.find('/', pos + 1);
      if (H5Lexists(id.get(), p.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
    }
    return true;
  }

  Handle open_dataset(const std::string& p) const {
    if (!exists(p)) fail("read", p, "no such dataset");
    return Handle(check(H5Dopen2(id.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Dclose);
  }

  std::vector<hsize_t> shape(hid_t dataset, const std::string& p) const {
    Handle space(check(H5Dget_space(dataset), "read", p), H5Sclose);
    int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 0) fail_h5("read", p);
    std::vector<hsize_t> dims(rank);
    if (rank > 0) check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), "read", p);
    return dims;
  }

  // Reads a whole numeric dataset into memory type `mem_type`, after checking its shape:
  // rank `expected.size()`, and each positive entry of `expected` exactly.
  template <typename T>
  std::vector<T> numbers(const std::string& p, hid_t mem_type,
                         const std::vector<long long>& expected,
                         std::vector<hsize_t>* dims_out = nullptr) const {
    Handle d = open_dataset(p);
    std::vector<hsize_t> dims = shape(d.get(), p);
    bool ok = dims.size() == expected.size();
    for (std::size_t k = 0; ok && k < dims.size(); ++k)
      ok = expected[k] < 0 || dims[k] == static_cast<hsize_t>(expected[k]);
    if (!ok) {
      std::vector<std::string> want;
      for (long long e : expected) want.push_back(e < 0 ? "any" : std::to_string(e));
      fail("read", p,
           fmt::format("shape is ({}), expected ({})", fmt::join(dims, ", "),
                       fmt::join(want, ", ")));
    }
    hsize_t total = 1;
    for (hsize_t n : dims) total *= n;
    std::vector<T> out(total);
    if (total > 0)
      check(H5Dread(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "read", p);
    if (dims_out) *dims_out = dims;
    return out;
  }

  // Reads a scalar numeric attribute `name` of the object at `p`.
  template <typename T>
  T scalar_attribute(const std::string& p, const std::string& name, hid_t mem_type) const {
    const std::string object = p + "@" + name;
    Handle obj(check(H5Oopen(id.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Oclose);
    htri_t present = H5Aexists(obj.get(), name.c_str());
    if (present <= 0) fail("read attribute", object, "no such attribute");
    Handle attr(check(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT), "open attribute", object),
                H5Aclose);
    Handle space(check(H5Aget_space(attr.get()), "read attribute", object), H5Sclose);
    if (H5Sget_simple_extent_npoints(space.get()) != 1)
      fail("read attribute", object, "expected a single value");
    T value{};
    check(H5Aread(attr.get(), mem_type, &value), "read attribute", object);
    return value;
  }

  // Reads string attribute `name` of `p` (scalar or 1-D, variable- or fixed-length).
  std::vector<std::string> string_attribute(const std::string& p, const std::string& name) const {
    const std::string object = p + "@" + name;
    Handle obj(check(H5Oopen(id.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Oclose);
    Handle attr(check(H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT), "open attribute", object),
                H5Aclose);
    Handle ftype(check(H5Aget_type(attr.get()), "read attribute", object), H5Tclose);
    if (H5Tget_class(ftype.get()) != H5T_STRING) fail("read attribute", object, "not text");
    Handle space(check(H5Aget_space(attr.get()), "read attribute", object), H5Sclose);
    hssize_t n = H5Sget_simple_extent_npoints(space.get());
    if (n < 0) fail_h5("read attribute", object);
    std::vector<std::string> out;
    if (n == 0) return out;
    if (H5Tis_variable_str(ftype.get()) > 0) {
      Handle mtype(check(H5Tcopy(H5T_C_S1), "read attribute", object), H5Tclose);
      check(H5Tset_size(mtype.get(), H5T_VARIABLE), "read attribute", object);
      // HDF5 converts no string between character sets, so read in the file's own.
      check(H5Tset_cset(mtype.get(), H5Tget_cset(ftype.get())), "read attribute", object);
      std::vector<char*> ptrs(n, nullptr);
      check(H5Aread(attr.get(), mtype.get(), ptrs.data()), "read attribute", object);
      for (char* s : ptrs) out.emplace_back(s ? s : "");
      free_vlen_strings(mtype.get(), space.get(), ptrs.data());
    } else {
      std::size_t size = H5Tget_size(ftype.get());
      std::vector<char> buf(size * n);
      check(H5Aread(attr.get(), ftype.get(), buf.data()), "read attribute", object);
      for (hssize_t i = 0; i < n; ++i) {
        std::string s(buf.data() + i * size, size);
        s.erase(s.find_last_not_of('\0') + 1);  // null padding or terminator
        out.push_back(s);
      }
    }
    return out;
  }

  bool has_attribute(const std::string& p, const std::string& name) const {
    if (!exists(p)) return false;
    Handle obj(check(H5Oopen(id.get(), p.c_str(), H5P_DEFAULT), "open", p), H5Oclose);
    return H5Aexists(obj.get(), name.c_str()) > 0;
  }
};

std::string normalise(std::string p) {
  if (p.empty() || p[0] != '/') p.insert(0, "/");
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  return p;
}

std::size_t count_snapshots(const File& f) {
  if (!f.exists("/snapshots")) return 0;
  // The writer sets "count" only after a snapshot is complete; a file from elsewhere may
  // lack it, and then every group counts.
  if (f.has_attribute("/snapshots", "count")) {
    auto n = f.scalar_attribute<std::int64_t>("/snapshots", "count", H5T_NATIVE_INT64);
    if (n < 0) f.fail("read attribute", "/snapshots@count", fmt::format("negative count {}", n));
    return static_cast<std::size_t>(n);
  }
  Handle g(f.check(H5Gopen2(f.id.get(), "/snapshots", H5P_DEFAULT), "open", "/snapshots"),
           H5Gclose);
  H5G_info_t info;
  f.check(H5Gget_info(g.get(), &info), "read", "/snapshots");
  return static_cast<std::size_t>(info.nlinks);
}

}  // namespace

std::size_t count_snapshots(const std::string& path) {
  File f(path);
  return count_snapshots(f);
}

SnapshotData read_snapshot(const std::string& path, long index) {
  File f(path);
  const std::size_t count = count_snapshots(f);
  long i = index < 0 ? index + static_cast<long>(count) : index;
  if (i < 0 || static_cast<std::size_t>(i) >= count)
    throw std::runtime_error(
        fmt::format("cannot read snapshot {} from {}: the file holds {}", index, path,
                    count == 1 ? std::string("1 snapshot") : fmt::format("{} snapshots", count)));
  const std::string g = fmt::format("/snapshots/{:06d}", i);
  if (!f.exists(g)) f.fail("read snapshot", g, "group missing although counted");

  SnapshotData s;
  s.step = f.scalar_attribute<std::int64_t>(g, "step", H5T_NATIVE_INT64);
  s.time = f.scalar_attribute<double>(g, "time", H5T_NATIVE_DOUBLE);
  auto dim = f.scalar_attribute<std::int64_t>(g, "dimension", H5T_NATIVE_INT64);
  if (dim != 2 && dim != 3) f.fail("read attribute", g + "@dimension", fmt::format("{}", dim));
  s.dimension = static_cast<int>(dim);

  s.id = f.numbers<std::int64_t>(g + "/id", H5T_NATIVE_INT64, {-1});
  const long long n = static_cast<long long>(s.id.size());
  s.radius = f.numbers<double>(g + "/radius", H5T_NATIVE_DOUBLE, {n});
  s.position = f.numbers<double>(g + "/position", H5T_NATIVE_DOUBLE, {n, dim});
  s.velocity = f.numbers<double>(g + "/velocity", H5T_NATIVE_DOUBLE, {n, dim});
  std::vector<hsize_t> spin_dims;
  s.spin = f.numbers<double>(g + "/spin", H5T_NATIVE_DOUBLE, {n, -1}, &spin_dims);
  if (spin_dims[1] != 1 && spin_dims[1] != 3)
    f.fail("read", g + "/spin", fmt::format("rows of {} values, expected 1 or 3", spin_dims[1]));
  s.spin_components = static_cast<int>(spin_dims[1]);
  s.material = f.numbers<std::int32_t>(g + "/material", H5T_NATIVE_INT32, {n});
  s.fixed = f.numbers<std::uint8_t>(g + "/fixed", H5T_NATIVE_UINT8, {n});
  if (f.has_attribute("/materials", "names"))
    s.material_names = f.string_attribute("/materials", "names");
  for (const std::string& name : s.material_names) {
    std::array<double, 3> properties;
    const char* keys[] = {"density", "young", "poisson"};
    for (int k = 0; k < 3; ++k)
      properties[k] =
          f.has_attribute("/materials/" + name, keys[k])
              ? f.scalar_attribute<double>("/materials/" + name, keys[k], H5T_NATIVE_DOUBLE)
              : std::numeric_limits<double>::quiet_NaN();
    s.material_properties.push_back(properties);
  }
  return s;
}

std::vector<double> read_series_column(const std::string& path, const std::string& group_path,
                                       const std::string& column) {
  File f(path);
  const std::string g = normalise(group_path);
  const std::string p = g == "/" ? "/" + column : g + "/" + column;
  if (!f.exists(p)) {
    std::string known;
    if (f.exists(g) && f.has_attribute(g, "columns"))
      known = fmt::format(" (columns: {})", fmt::join(f.string_attribute(g, "columns"), ", "));
    f.fail("read series column", p, "no such column" + known);
  }
  return f.numbers<double>(p, H5T_NATIVE_DOUBLE, {-1});
}

std::string read_text(const std::string& path, const std::string& dataset_path) {
  File f(path);
  const std::string p = normalise(dataset_path);
  Handle d = f.open_dataset(p);
  Handle ftype(f.check(H5Dget_type(d.get()), "read", p), H5Tclose);
  if (H5Tget_class(ftype.get()) != H5T_STRING) f.fail("read text", p, "not a text dataset");
  Handle space(f.check(H5Dget_space(d.get()), "read", p), H5Sclose);
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    f.fail("read text", p, "expected a single string");
  if (H5Tis_variable_str(ftype.get()) > 0) {
    Handle mtype(f.check(H5Tcopy(H5T_C_S1), "read", p), H5Tclose);
    f.check(H5Tset_size(mtype.get(), H5T_VARIABLE), "read", p);
    f.check(H5Tset_cset(mtype.get(), H5Tget_cset(ftype.get())), "read", p);
    char* ptr = nullptr;
    f.check(H5Dread(d.get(), mtype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr), "read", p);
    std::string out = ptr ? ptr : "";
    free_vlen_strings(mtype.get(), space.get(), &ptr);
    return out;
  }
  std::size_t size = H5Tget_size(ftype.get());
  std::string out(size, '\0');
  f.check(H5Dread(d.get(), ftype.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "read", p);
  out.erase(out.find_last_not_of('\0') + 1);  // null padding or terminator
  return out;
}

}  // namespace granule::io
