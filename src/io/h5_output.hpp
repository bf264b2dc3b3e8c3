// Writes a run's results to one HDF5 file (C API, serial): scene provenance
// as text datasets and attributes, extendible time series, and particle
// snapshots. Layout ("granule-1"):
//   /                      attrs format="granule-1", created (ISO 8601, UTC), hdf5_version
//   /<series group>        attr columns (string array, in declaration order);
//                          one extendible float64 dataset per column, attr units (and
//                          unit, when the declaration gave units)
//   /snapshots             attr count (int64): number of complete snapshots
//   /snapshots/NNNNNN      datasets id, radius, position, velocity, spin, material, fixed,
//                          optionally force, torque; attrs step, time, dimension
//   /snapshots/NNNNNN/contacts  optional: datasets i, j (-1 for a wall), wall (-1 for a
//                          pair), overlap, normal_force, tangential_force, normal
//   every numeric dataset carries attr units (io/output_units.hpp)
//   /materials             attr names (string array): material index -> name
// Every failure throws std::runtime_error naming the file and the object.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace granule::io {

struct SnapshotView {  // plain pointers into the engine's arrays; nothing owned
  std::int64_t step = 0;
  double time = 0;                         // s
  int dimension = 3;                       // 2 or 3: width of position/velocity rows
  int spin_components = 3;                 // 1 in 2D (spin about z), 3 in 3D
  std::size_t count = 0;                   // number of particles
  const std::int64_t* id = nullptr;        // persistent ids
  const double* radius = nullptr;          // m
  const double* position = nullptr;        // count*dimension, row-major, m
  const double* velocity = nullptr;        // count*dimension, m/s
  const double* spin = nullptr;            // count*spin_components, rad/s
  const std::int32_t* material = nullptr;  // index into material_names
  const std::uint8_t* fixed = nullptr;     // 1 = fixed particle (infinite mass)
  std::vector<std::string> material_names;
  // Optional: the last step's force and torque (rows as velocity and spin), and the
  // contact network (`contacts` rows; tangential_force and normal rows of `dimension`).
  const double* force = nullptr;   // N
  const double* torque = nullptr;  // N m
  bool with_contacts = false;
  std::size_t contacts = 0;
  const std::int64_t* contact_i = nullptr;
  const std::int64_t* contact_j = nullptr;           // -1: a wall contact
  const std::int32_t* contact_wall = nullptr;        // wall index, -1: a pair
  const double* contact_overlap = nullptr;           // m
  const double* contact_normal_force = nullptr;      // N
  const double* contact_tangential_force = nullptr;  // N, on i
  const double* contact_normal = nullptr;            // unit vector from j (or the wall) to i
  // Optional: the parallel bonds (contact/parallel_bond.hpp), `bonds` rows in the order made.
  std::size_t bonds = 0;
  const std::int64_t* bond_a = nullptr;  // ids, a < b; nullptr: the scene has no bonds
  const std::int64_t* bond_b = nullptr;
  const std::uint8_t* bond_broken = nullptr;  // 1: broken
};

// After a failed write to `path`: "no space left on the disk holding <dir> (N KiB free)"
// when the file system is full (`detail`, the library's message, says ENOSPC, or under
// 1 MiB is left), "the file would pass this process's file size limit (N KiB; ulimit -f)"
// when `detail` says EFBIG under a limit, else "" (another cause, which `detail` gives).
std::string disk_full_note(const std::string& path, const std::string& detail);
// A write that would pass a file size limit (EFBIG): "the file would pass this process's
// file size limit (N KiB; ulimit -f)" under one, else the file system's largest file.
std::string file_too_large_note();

// The description of the HDF5 error just raised (innermost first; "" if none), made short:
// a failed write says "file write failed: No space left on device". Call it before any
// other HDF5 function, which would clear the error.
std::string hdf5_error_text();

// Asks HDF5 not to close the files still open when the program exits: the only ones are
// files whose writes failed (H5Output leaves them as the last flush wrote them), and
// closing one would flush a cache that no longer matches it. Call before any other
// HDF5 function (first thing in main).
void keep_hdf5_files_at_exit();

// reopen()'s refusal of a file another run wrote in the first run's place.
struct OutputOfAnotherRun : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class H5Output {
 public:
  // Creates or truncates `path`; root attrs format="granule-1", created (ISO time string).
  explicit H5Output(const std::string& path);
  ~H5Output();  // writes buffered series rows, closes; never throws
  H5Output(const H5Output&) = delete;
  H5Output& operator=(const H5Output&) = delete;

  const std::string& path() const;

  // Scalar variable-length UTF-8 text dataset, e.g. "/scene/source"; intermediate groups are
  // created, an existing dataset of that name is replaced.
  void write_text(const std::string& dataset_path, const std::string& text);

  // Attributes on an existing object (group or dataset) or on a new group (created with its
  // parents). An existing attribute of that name is replaced.
  void write_attribute(const std::string& group_path, const std::string& name,
                       double value);  // non-finite -> throw
  void write_attribute(const std::string& group_path, const std::string& name, std::int64_t value);
  void write_attribute(const std::string& group_path, const std::string& name,
                       const std::string& value);
  void write_attribute(const std::string& group_path, const std::string& name,
                       const std::vector<double>& value);  // non-finite -> throw

  // Why the run stopped, as the root's attribute "failure". Unlike the writes above, also
  // after a write was refused for want of room (a full disk, a quota, the file size
  // limit: the file is whole up to that write), where the room for this one attribute
  // and its metadata can still be set aside. Returns whether it was written; never throws.
  bool record_failure(const std::string& message) noexcept;

  // Time series: a group holding one chunked, extendible 1-D float64 dataset per column
  // (h5py reads f["/series/time"][:]). Declaring the same group twice with the same columns
  // is a no-op; with different columns it throws. Units, if given, become a "unit" attr on
  // each dataset.
  void series_declare(const std::string& group_path, const std::vector<std::string>& columns,
                      const std::vector<std::string>& units = {});
  // Sets the "units" attribute of each column of a declared series (one unit for
  // several columns: each but `time`, which is in s); false (and nothing written)
  // when `group_path` is no series or `units` has neither one entry nor one per column.
  bool set_series_units(const std::string& group_path, const std::vector<std::string>& units);
  // Appends one row (row.size() must equal the column count). A non-finite value throws
  // naming the column, and the row is not appended.
  // Rows are buffered in memory and written when 1024 rows are pending or 0.5 s of wall
  // time has passed since the series was last written (checked at each append), and always
  // on flush(), write_snapshot() and destruction; each batch written is followed by a flush
  // to disk. So a crash loses at most the last ~0.5 s of rows, at a cost of at most two
  // disk flushes per second however often rows arrive.
  void series_append(const std::string& group_path, const std::vector<double>& row);

  // Writes /snapshots/NNNNNN (running index from 000000) and updates /snapshots attr count;
  // writes /materials attr names when it changes. Non-finite radius/position/velocity/spin
  // throws naming the particle id and quantity, and nothing of that snapshot is written.
  // Returns the group path written, e.g. "/snapshots/000003".
  std::string write_snapshot(const SnapshotView& snapshot);

  // Writes buffered series rows and pushes everything to disk (H5Fflush).
  void flush();
  // flush(), then the file as it is now becomes what a restart can put it back to,
  // whatever moment the process dies after (io/journalled_file.hpp). Returns the
  // file's id, which restore() asks for.
  std::uint64_t mark();
  // Puts `target` (the file `original` or a copy of it) back as `original` stood at
  // its last mark(), when its journal is there and is of the file `file_id`; false
  // (nothing changed) when there is none.
  static bool restore(const std::string& original, const std::string& target,
                      std::uint64_t file_id);
  // Removes the journal beside `path` (a file about to be replaced).
  static void forget_journal(const std::string& path);

  std::size_t snapshot_count() const;

  // ---- continuing a file (a restarted run) ----
  // Rows in each series (after flush()): group path -> rows.
  std::map<std::string, std::int64_t> series_rows() const;
  // The columns of a declared series ("/series"), in declaration order; empty if none.
  std::vector<std::string> series_columns(const std::string& group_path) const;
  // Names of the attributes on an existing group ("/results"); empty if it is absent.
  std::vector<std::string> attribute_names(const std::string& group_path) const;
  // Names of the objects at the file's top ("snapshots", "series", ...).
  std::vector<std::string> top_level_names() const;
  // What the file held at a mark, beyond its snapshots and series: its top-level
  // objects and the attributes on its root and on `attribute_group` ("/results").
  struct Kept {
    std::vector<std::string> top_level, root_attributes;
    std::string attribute_group;
    std::vector<std::string> attributes;
  };
  // Opens an existing file written by H5Output and cuts it back to a mark: the first
  // `snapshots` snapshots, each listed series at its row count (series not listed are
  // removed), and the top-level objects and attributes `kept` lists (others removed:
  // what a run wrote after the mark, as a scene's save_contact_histories or a
  // failure). Refused unless the file is the one the mark's run wrote: its root's
  // `file_id` is `file_id` (another run may have written a new file there since).
  // Marked (mark()) before it is cut, under `file_id`.
  static std::unique_ptr<H5Output> reopen(const std::string& path, std::size_t snapshots,
                                          const std::map<std::string, std::int64_t>& series_rows,
                                          const Kept& kept, std::uint64_t file_id);

 private:
  H5Output();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granule::io
