// An XDMF 2 descriptor beside the HDF5 output (out.h5 -> out.xmf), so that
// ParaView (and VisIt) open the snapshots directly: a temporal collection of
// Polyvertex grids whose geometry and attributes (radius, velocity, spin,
// material, fixed, id) point into /snapshots/NNNNNN of the HDF5 file; and
// beside it out_walls.xmf with the walls as small inline geometries (2D:
// polylines in z = 0; 3D: a quadrilateral for a plane, a tube for a
// cylinder, its triangles for a mesh), clipped to the region the particles
// occupy. The XML files are rewritten whole (through a temporary file and a
// rename, so a reader never sees half a file) from each snapshot's text, made
// once when the snapshot is added: after a snapshot or at the output's periodic
// flush when due, that is unless the last rewrite took more than a twentieth of
// the time since it (a long run's index grows with its snapshots, and rewriting
// it at each would make the run's cost grow with their square), and always at
// flush() (a checkpoint, a failure, the output's end).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/simulation_base.hpp"

namespace granule::io {

struct XdmfShape {  // one wall's inline geometry
  std::string name;
  std::string topology;  // "Polyline" or "Quadrilateral"
  int nodes_per_element = 0;
  std::vector<double> points;     // x, y, z per node
  std::vector<int> connectivity;  // nodes_per_element entries per element
  bool operator==(const XdmfShape& o) const {
    return name == o.name && topology == o.topology && points == o.points &&
           connectivity == o.connectivity;
  }
};

struct XdmfSnapshot {
  std::string group;  // "/snapshots/000003"
  double time = 0;    // s
  std::int64_t step = 0;
  std::size_t count = 0;  // particles
  int dimension = 3;
  std::vector<XdmfShape> walls;
};

// "out.h5" -> "out.xmf"; "out" -> "out.xmf".
std::string xdmf_path_for(const std::string& h5_path);
// "out.h5" -> "out_walls.xmf": the walls' grids, apart from the particles'.
std::string xdmf_walls_path_for(const std::string& h5_path);

// The walls as drawable shapes within `extent` (x0, x1, y0, y1, z0, z1 [m]).
std::vector<XdmfShape> wall_shapes(const std::vector<WallSpec>& walls, int dimension,
                                   const std::array<double, 6>& extent);

// The mesh walls' triangles where they are now, into their walls' shapes
// (wall_shapes() leaves those empty).
void add_mesh_shapes(std::vector<XdmfShape>& shapes, const std::vector<MeshView>& meshes);

class XdmfIndex {
 public:
  explicit XdmfIndex(std::string h5_path);
  const std::string& path() const { return path_; }
  const std::string& walls_path() const { return walls_path_; }
  // Records a snapshot and rewrites the files when due (above); throws
  // std::runtime_error if it cannot write them.
  void add(XdmfSnapshot snapshot);
  // Rewrites the files if a snapshot was added since they were last written.
  void flush();
  // The same where due (above).
  void flush_if_due() {
    if (stale_ && due()) write();
  }
  bool written() const { return !stale_; }  // the files hold every snapshot added
  std::string text() const;                 // the particles' XML as it would be written now
  std::string walls_text() const;           // the walls' XML; empty when no snapshot has walls
  const std::vector<XdmfSnapshot>& snapshots() const { return snapshots_; }
  // Replaces the index by `snapshots` (a continued run) and rewrites the file.
  void restore(std::vector<XdmfSnapshot> snapshots);

 private:
  void write();
  bool due() const;
  // walls_fixed_ from all the snapshots, and wall_grids_ to match.
  void find_walls_fixed();
  void make_wall_grids();

  std::string h5_name_;  // as referenced from the XML: the file name, since both lie together
  std::string path_;
  std::string walls_path_;
  std::vector<XdmfSnapshot> snapshots_;
  // Per snapshot, its particles' grid and, once the walls have moved
  // (!walls_fixed_), its walls' spatial collection with its time, as XML; empty
  // where it has none. While the walls stay as they were, the file shows the
  // first snapshot's walls and no per-snapshot text is kept.
  std::vector<std::string> particle_grids_, wall_grids_;
  std::size_t first_walls_ = SIZE_MAX;  // the first snapshot with walls, if any
  bool walls_fixed_ = true;             // every snapshot with walls has the first one's walls
  bool stale_ = false;                  // a snapshot was added since the files were written
  std::chrono::steady_clock::time_point last_write_{};
  double last_write_seconds_ = -1;  // how long the last rewrite took; < 0: none yet
};

}  // namespace granule::io
