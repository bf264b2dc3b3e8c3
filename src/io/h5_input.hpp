// Reads files written by H5Output back: to reload a saved agglomerate, to
// restart, and in tests. Files are opened read-only with HDF5 file locking
// turned off (where the library supports it), so that a file whose writer is
// still running, or crashed while holding the lock, can be read up to its last
// flush. Every failure throws std::runtime_error naming the file and object.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace granule::io {

struct SnapshotData {
  std::int64_t step = 0;
  double time = 0;          // s
  int dimension = 3;        // width of position/velocity rows
  int spin_components = 3;  // width of spin rows
  std::vector<std::int64_t> id;
  std::vector<double> radius, position, velocity, spin;  // row-major, as written
  std::vector<std::int32_t> material;
  std::vector<std::uint8_t> fixed;
  std::vector<std::string> material_names;  // from /materials attr names; empty if absent
  // Each named material's density [kg/m^3], young [Pa] and poisson as the file
  // recorded them (/materials/<name>); NaN where it did not.
  std::vector<std::array<double, 3>> material_properties;
};

// Number of complete snapshots (the /snapshots attr count); 0 if the file has none.
std::size_t count_snapshots(const std::string& path);

// index counts from 0; negative counts from the end (-1 = last). Throws naming the file and
// index if there is no such snapshot.
SnapshotData read_snapshot(const std::string& path, long index = -1);

std::vector<double> read_series_column(const std::string& path, const std::string& group_path,
                                       const std::string& column);

// Reads a scalar string dataset (variable- or fixed-length), e.g. "/scene/source".
std::string read_text(const std::string& path, const std::string& dataset_path);

}  // namespace granule::io
