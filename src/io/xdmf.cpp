#include "io/xdmf.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/h5_output.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

namespace {

constexpr double two_pi = 6.28318530717958647692;
constexpr int circle_segments = 96;  // a circle drawn as a polygon: < 0.06 % radius error

std::string join(const std::vector<double>& v) {
  std::string out;
  for (std::size_t k = 0; k < v.size(); ++k) out += fmt::format(k ? " {:.9g}" : "{:.9g}", v[k]);
  return out;
}
std::string join(const std::vector<int>& v) {
  std::string out;
  for (std::size_t k = 0; k < v.size(); ++k) out += fmt::format(k ? " {}" : "{}", v[k]);
  return out;
}

std::string xml_attr(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '"')
      out += "&quot;";
    else if (static_cast<unsigned char>(c) >= 0x20)
      out += c;
  }
  return out;
}

using V3 = std::array<double, 3>;
V3 sub(const V3& a, const V3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V3 add(const V3& a, const V3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
V3 scale(const V3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double dot(const V3& a, const V3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V3 unit(const V3& a) {
  double n = std::sqrt(dot(a, a));
  return n > 0 ? scale(a, 1 / n) : V3{1, 0, 0};
}
// Two unit vectors perpendicular to n and to each other.
void basis(const V3& n, V3& t1, V3& t2) {
  V3 helper = std::abs(n[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  t1 = unit(cross(n, helper));
  t2 = cross(n, t1);
}

// A finite wall's own shape (geometry/finite_walls.hpp), not clipped: a
// rectangle's quadrilateral (2D: its segment); a disk's, tube's or cone's band
// of quadrilaterals between its two rim circles (2D: its two mirrored segments).
XdmfShape finite_wall_shape(const WallSpec& w, int dimension) {
  XdmfShape s;
  s.name = w.name;
  const V3 origin = w.type == WallType::plane ? w.point : w.center;
  auto push = [&](const V3& q) { s.points.insert(s.points.end(), q.begin(), q.end()); };
  if (w.type == WallType::plane) {
    const V3 n = unit(w.normal), u = unit(w.side);
    if (dimension == 2) {
      s.topology = "Polyline";
      for (double a : {-0.5, 0.5}) push(add(origin, scale(u, a * w.size_a)));
      s.connectivity = {0, 1};
      s.nodes_per_element = 2;
      return s;
    }
    const V3 v = cross(n, u);
    s.topology = "Quadrilateral";
    for (auto [a, b] : {std::pair{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}})
      push(add(origin, add(scale(u, a * w.size_a), scale(v, b * w.size_b))));
    s.connectivity = {0, 1, 2, 3};
    s.nodes_per_element = 4;
    return s;
  }
  // The meridian segment from (rho0, z0) to (rho1, z1) about the axis.
  const V3 axis = unit(w.type == WallType::disk ? w.normal : w.axis);
  const double rho[2] = {w.type == WallType::disk ? w.inner_radius : w.radius_lo,
                         w.type == WallType::disk ? w.radius : w.radius_hi};
  const double z[2] = {w.z_lo, w.z_hi};
  if (dimension == 2) {
    s.topology = "Polyline";
    const V3 e{-axis[1], axis[0], 0};
    for (double side : {-1.0, 1.0})
      for (int end = 0; end < 2; ++end)
        push(add(origin, add(scale(axis, z[end]), scale(e, side * rho[end]))));
    s.connectivity = {0, 1, 2, 3};
    s.nodes_per_element = 2;
    return s;
  }
  s.topology = "Quadrilateral";
  V3 t1, t2;
  basis(axis, t1, t2);
  const int m = circle_segments;
  for (int end = 0; end < 2; ++end)
    for (int k = 0; k < m; ++k) {
      const double a = two_pi * k / m;
      push(add(add(origin, scale(axis, z[end])),
               add(scale(t1, rho[end] * std::cos(a)), scale(t2, rho[end] * std::sin(a)))));
    }
  for (int k = 0; k < m; ++k) {
    const int next = (k + 1) % m;
    s.connectivity.insert(s.connectivity.end(), {k, next, m + next, m + k});
  }
  s.nodes_per_element = 4;
  return s;
}

}  // namespace

std::string xdmf_path_for(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension(".xmf");
  return p.string();
}

std::vector<XdmfShape> wall_shapes(const std::vector<WallSpec>& walls, int dimension,
                                   const std::array<double, 6>& e) {
  const V3 centre{(e[0] + e[1]) / 2, (e[2] + e[3]) / 2, (e[4] + e[5]) / 2};
  const double half_diagonal =
      0.5 * std::sqrt((e[1] - e[0]) * (e[1] - e[0]) + (e[3] - e[2]) * (e[3] - e[2]) +
                      (e[5] - e[4]) * (e[5] - e[4]));
  std::vector<XdmfShape> out;
  for (const auto& w : walls) {
    if (w.finite()) {
      out.push_back(finite_wall_shape(w, dimension));
      continue;
    }
    XdmfShape s;
    s.name = w.name;
    const V3 normal = unit(w.normal);
    if (dimension == 2) {
      s.topology = "Polyline";
      if (w.type == WallType::polyline) {
        // its outline: add_mesh_shapes()
      } else if (w.type == WallType::cylinder) {
        for (int k = 0; k < circle_segments; ++k) {
          double a = two_pi * k / circle_segments;
          s.points.insert(s.points.end(), {w.center[0] + w.radius * std::cos(a),
                                           w.center[1] + w.radius * std::sin(a), 0.0});
          s.connectivity.push_back(k);
        }
        s.connectivity.push_back(0);  // closed
      } else {
        // The segment of the line through the extent's centre's projection.
        V3 p{w.point[0], w.point[1], 0};
        V3 n{normal[0], normal[1], 0};
        V3 foot = sub(centre, scale(n, dot(sub(centre, p), n)));
        foot[2] = 0;
        V3 t{-n[1], n[0], 0};
        for (double sgn : {-1.0, 1.0}) {
          V3 q = add(foot, scale(t, sgn * half_diagonal));
          s.points.insert(s.points.end(), q.begin(), q.end());
        }
        s.connectivity = {0, 1};
      }
      s.nodes_per_element = static_cast<int>(s.connectivity.size());
    } else if (w.type == WallType::mesh) {
      s.topology = "Triangle";  // its triangles: add_mesh_shapes()
      s.nodes_per_element = 3;
    } else if (w.type == WallType::plane) {
      s.topology = "Quadrilateral";
      V3 foot = sub(centre, scale(normal, dot(sub(centre, w.point), normal)));
      V3 t1, t2;
      basis(normal, t1, t2);
      const double h = half_diagonal;
      for (auto [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        V3 q = add(foot, add(scale(t1, a * h), scale(t2, b * h)));
        s.points.insert(s.points.end(), q.begin(), q.end());
      }
      s.connectivity = {0, 1, 2, 3};
      s.nodes_per_element = 4;
    } else {
      // A tube over the part of the axis the extent box spans.
      s.topology = "Quadrilateral";
      const V3 axis = unit(w.axis);
      double lo = 1e300, hi = -1e300;
      for (int corner = 0; corner < 8; ++corner) {
        V3 c{e[corner & 1 ? 1 : 0], e[corner & 2 ? 3 : 2], e[corner & 4 ? 5 : 4]};
        double t = dot(sub(c, w.center), axis);
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
      V3 t1, t2;
      basis(axis, t1, t2);
      const int m = circle_segments / 2;
      for (double along : {lo, hi})
        for (int k = 0; k < m; ++k) {
          double a = two_pi * k / m;
          V3 q = add(add(w.center, scale(axis, along)),
                     add(scale(t1, w.radius * std::cos(a)), scale(t2, w.radius * std::sin(a))));
          s.points.insert(s.points.end(), q.begin(), q.end());
        }
      for (int k = 0; k < m; ++k) {
        int next = (k + 1) % m;
        s.connectivity.insert(s.connectivity.end(), {k, next, m + next, m + k});
      }
      s.nodes_per_element = 4;
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::string xdmf_walls_path_for(const std::string& h5_path) {
  std::filesystem::path p(h5_path);
  p.replace_extension();
  return p.string() + "_walls.xmf";
}

void add_mesh_shapes(std::vector<XdmfShape>& shapes, const std::vector<MeshView>& meshes) {
  for (const auto& m : meshes) {
    if (m.wall < 0 || static_cast<std::size_t>(m.wall) >= shapes.size()) continue;
    XdmfShape& s = shapes[m.wall];
    s.points.clear();
    s.connectivity.clear();
    for (const auto& x : m.vertices) s.points.insert(s.points.end(), x.begin(), x.end());
    for (const auto& t : m.triangles)
      for (auto c : t) s.connectivity.push_back(static_cast<int>(c));
    if (!m.lines.empty()) {  // a polyline's outline, drawn in order: one element
      s.connectivity.push_back(static_cast<int>(m.lines.front()[0]));
      for (const auto& l : m.lines) s.connectivity.push_back(static_cast<int>(l[1]));
      s.nodes_per_element = static_cast<int>(s.connectivity.size());
    }
  }
}

XdmfIndex::XdmfIndex(std::string h5_path)
    : h5_name_(std::filesystem::path(h5_path).filename().string()),
      path_(xdmf_path_for(h5_path)),
      walls_path_(xdmf_walls_path_for(h5_path)) {}

namespace {

// Writes beside the target and renames: a reader never sees half a file.
void write_whole(const std::string& named, const std::string& text) {
  const std::string path = writable_path(named);
  const std::string tmp = path + ".tmp";
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw std::runtime_error(
          fmt::format("cannot write XDMF file '{}': {}", tmp, std::strerror(errno)));
    out << text;
    out.close();
    if (!out) {
      // A full disk: the half-written index goes, the previous one stays in place.
      const std::string why = errno ? std::strerror(errno) : "write failed";
      std::remove(tmp.c_str());
      const std::string full = disk_full_note(path, why);
      throw std::runtime_error(
          fmt::format("writing XDMF file '{}' failed: {}; '{}' is kept as it was", tmp,
                      full.empty() ? why : full, path));
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("cannot replace XDMF file '{}'", path));
  }
}

// One snapshot's particles as a Polyvertex grid pointing into the HDF5 file
// `h5`; empty for a snapshot without particles (a grid of no points is not
// valid XDMF).
std::string particle_grid(const XdmfSnapshot& s, const std::string& h5) {
  if (s.count == 0) return {};
  const std::size_t n = s.count;
  const int d = s.dimension;
  auto item = [&](const char* dataset, const std::string& dims, const char* type, int precision) {
    return fmt::format(
        "  <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" "
        "Format=\"HDF\">{}:{}/{}</DataItem>\n",
        dims, type, precision, h5, s.group, dataset);
  };
  auto attribute = [&](const char* name, const char* kind, const std::string& dims,
                       const char* type, int precision) {
    return fmt::format("  <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n", name,
                       kind) +
           item(name, dims, type, precision) + "  </Attribute>\n";
  };
  std::string x = fmt::format(" <Grid Name=\"{}\" GridType=\"Uniform\">\n",
                              s.group.substr(s.group.rfind('/') + 1));
  x += fmt::format("  <Time Value=\"{:.17g}\"/>\n", s.time);
  x += fmt::format(
      "  <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\"/>\n",
      n);
  x += fmt::format("  <Geometry GeometryType=\"{}\">\n", d == 2 ? "XY" : "XYZ");
  x += item("position", fmt::format("{} {}", n, d), "Float", 8);
  x += "  </Geometry>\n";
  x += attribute("radius", "Scalar", fmt::format("{}", n), "Float", 8);
  x += attribute("velocity", "Vector", fmt::format("{} {}", n, d), "Float", 8);
  x += attribute("spin", d == 2 ? "Scalar" : "Vector", fmt::format("{} {}", n, d == 2 ? 1 : 3),
                 "Float", 8);
  x += attribute("material", "Scalar", fmt::format("{}", n), "Int", 4);
  x += attribute("fixed", "Scalar", fmt::format("{}", n), "UChar", 1);
  x += attribute("id", "Scalar", fmt::format("{}", n), "Int", 8);
  x += " </Grid>\n";
  return x;
}

// One wall's shape as a grid of inline XML data.
std::string shape_grid(const XdmfShape& w, const std::string& name) {
  const std::size_t nodes = w.points.size() / 3;
  const std::size_t elements = w.connectivity.size() / w.nodes_per_element;
  std::string g = fmt::format(" <Grid Name=\"{}\" GridType=\"Uniform\">\n", xml_attr(name));
  g += fmt::format(
      "  <Topology TopologyType=\"{}\" NumberOfElements=\"{}\" NodesPerElement=\"{}\">\n"
      "   <DataItem Dimensions=\"{} {}\" NumberType=\"Int\" Precision=\"4\" "
      "Format=\"XML\">{}</DataItem>\n"
      "  </Topology>\n",
      w.topology, elements, w.nodes_per_element, elements, w.nodes_per_element,
      join(w.connectivity));
  g += fmt::format(
      "  <Geometry GeometryType=\"XYZ\">\n"
      "   <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
      "Format=\"XML\">{}</DataItem>\n"
      "  </Geometry>\n </Grid>\n",
      nodes, join(w.points));
  return g;
}

// The walls as a spatial collection, at `time` where they moved (else shown at every time).
std::string spatial_walls(const std::vector<XdmfShape>& walls, const double* time,
                          const std::string& name) {
  std::string g =
      fmt::format("<Grid Name=\"{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", name);
  if (time) g += fmt::format(" <Time Value=\"{:.17g}\"/>\n", *time);
  for (const auto& w : walls) g += shape_grid(w, "wall_" + w.name);
  return g + "</Grid>\n";
}

std::string timed_walls(const XdmfSnapshot& s) {
  if (s.walls.empty()) return {};
  return spatial_walls(s.walls, &s.time, s.group.substr(s.group.rfind('/') + 1));
}

}  // namespace

void XdmfIndex::restore(std::vector<XdmfSnapshot> snapshots) {
  snapshots_.clear(), particle_grids_.clear(), wall_grids_.clear();
  first_walls_ = SIZE_MAX, walls_fixed_ = true;
  if (snapshots.empty()) return;
  XdmfSnapshot last = std::move(snapshots.back());
  snapshots.pop_back();
  for (auto& s : snapshots) {
    particle_grids_.push_back(particle_grid(s, xml_attr(h5_name_)));
    snapshots_.push_back(std::move(s));
  }
  find_walls_fixed();
  add(std::move(last));
  flush();
}

void XdmfIndex::find_walls_fixed() {
  first_walls_ = SIZE_MAX, walls_fixed_ = true;
  for (std::size_t k = 0; k < snapshots_.size(); ++k) {
    if (snapshots_[k].walls.empty()) continue;
    if (first_walls_ == SIZE_MAX)
      first_walls_ = k;
    else
      walls_fixed_ = walls_fixed_ && snapshots_[k].walls == snapshots_[first_walls_].walls;
  }
  make_wall_grids();
}

void XdmfIndex::make_wall_grids() {
  wall_grids_.clear();
  if (walls_fixed_) return;
  for (const auto& s : snapshots_) wall_grids_.push_back(timed_walls(s));
}

void XdmfIndex::add(XdmfSnapshot snapshot) {
  // A second snapshot of one step (the final state, after a callback changed the
  // step's particles once its snapshot was written) supersedes the first in the
  // index: viewers show one grid per time. One without particles has no grid
  // (particle_grid), so it leaves the step's first in place rather than drop both.
  if (!snapshots_.empty() && snapshots_.back().step == snapshot.step) {
    if (snapshot.count == 0) return;  // nothing changes
    particle_grids_.back() = particle_grid(snapshot, xml_attr(h5_name_));
    snapshots_.back() = std::move(snapshot);
    find_walls_fixed();
  } else {
    particle_grids_.push_back(particle_grid(snapshot, xml_attr(h5_name_)));
    snapshots_.push_back(std::move(snapshot));
    const XdmfSnapshot& added = snapshots_.back();
    if (!walls_fixed_) {
      wall_grids_.push_back(timed_walls(added));
    } else if (!added.walls.empty()) {
      if (first_walls_ == SIZE_MAX) {
        first_walls_ = snapshots_.size() - 1;
      } else if (!(added.walls == snapshots_[first_walls_].walls)) {
        walls_fixed_ = false;  // from now on a temporal collection: every snapshot's walls
        make_wall_grids();
      }
    }
  }
  stale_ = true;
  if (due()) write();
}

bool XdmfIndex::due() const {
  const double since =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_write_).count();
  return last_write_seconds_ < 0 || since >= 20 * last_write_seconds_;
}

void XdmfIndex::flush() {
  if (stale_) write();
}

void XdmfIndex::write() {
  const auto start = std::chrono::steady_clock::now();
  write_whole(path_, text());
  const std::string walls = walls_text();
  if (!walls.empty())
    write_whole(walls_path_, walls);
  else
    std::remove(walls_path_.c_str());  // not a previous run's walls beside these particles
  stale_ = false;
  last_write_ = std::chrono::steady_clock::now();
  last_write_seconds_ = std::chrono::duration<double>(last_write_ - start).count();
}

std::string XdmfIndex::text() const {
  std::string x =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<!-- Written by granule beside the HDF5 file it describes; open this file in ParaView\n"
      "     (Xdmf Reader) and use Glyph (Sphere, Scale Array = radius, Scale Factor 2) or\n"
      "     Point Gaussian to see the particles; the walls are in <name>_walls.xmf. -->\n"
      "<Xdmf Version=\"2.0\">\n<Domain>\n"
      "<Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& grid : particle_grids_) x += grid;
  x += "</Grid>\n";
  x += "</Domain>\n</Xdmf>\n";
  return x;
}

// The walls live in a file of their own so that a Glyph over the particles'
// file sees only particles (wall vertices have no radius and would be glyphed
// at the scale factor), and so that the Xdmf3 readers, which read the first
// grid of a domain only, show them too.
std::string XdmfIndex::walls_text() const {
  if (first_walls_ == SIZE_MAX) return {};
  std::string x =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<!-- Written by granule: the walls of the run whose particles are in the .xmf of\n"
      "     the same name without _walls; show them as Surface (3D) or Wireframe (2D). -->\n"
      "<Xdmf Version=\"2.0\">\n<Domain>\n";
  // One top-level grid (the Xdmf3 readers read no other): a spatial collection
  // of the walls, without a time if they never changed (shown at every time);
  // if any of them moved, a temporal collection of such spatial collections,
  // one per snapshot.
  if (walls_fixed_) {
    x += spatial_walls(snapshots_[first_walls_].walls, nullptr, "walls");
  } else {
    x += "<Grid Name=\"walls\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& grid : wall_grids_) x += grid;
    x += "</Grid>\n";
  }
  x += "</Domain>\n</Xdmf>\n";
  return x;
}

}  // namespace granule::io
