// Mesh walls in the engine: declaring one from its file, the grids their
// contact searches use, this step's contacts (before the wall kernels), their
// poses in checkpoints, and their triangles where they are now for output.
// A 2D scene's polyline walls (declared in simulation_polylines.cpp) share
// all but the grids.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/fnv1a.hpp"
#include "core/plain_name.hpp"
#include "engine/simulation.hpp"
#include "kernel/mesh_contacts.hpp"

namespace granule {

template <int D>
int Simulation<D>::add_mesh_wall(const MeshWallSpec& s, Triangles mesh) {
  const std::string ctx = fmt::format("wall_mesh '{}'", s.name);
  if constexpr (D == 2) {
    (void)mesh;
    throw InputError(fmt::format(
        "{}: mesh walls are triangle surfaces, for 3D scenes; a 2D scene draws its shapes with "
        "polyline walls (line segments and arcs)",
        ctx));
  } else {
    check_plain_name(s.name, "wall_mesh");
    for (const auto& w : walls_)
      if (w.name == s.name) throw InputError(fmt::format("wall '{}' is declared twice", s.name));
    if (s.material < 0 || s.material >= static_cast<int>(materials_.size()))
      throw InputError(fmt::format("{}: unknown material", ctx));
    if (!finite3(s.velocity) || !finite3(s.axis_point) || !finite3(s.axis) ||
        !std::isfinite(s.angular_velocity))
      throw InputError(
          fmt::format("{}: velocity, angular_velocity, axis and axis_point must be finite", ctx));
    const V axis = to_vec(s.axis);
    if (!(axis.norm() > 0)) throw InputError(fmt::format("{}: axis must be non-zero", ctx));
    if (mesh.triangles.empty()) throw InputError(fmt::format("{}: the mesh has no triangles", ctx));
    for (const auto& x : mesh.vertices)
      if (!x.allFinite()) throw InputError(fmt::format("{}: a vertex is not finite", ctx));
    for (const auto& t : mesh.triangles)
      for (auto c : t)
        if (c >= mesh.vertices.size())
          throw InputError(fmt::format("{}: a triangle names a vertex that does not exist", ctx));
    for (const auto& line : s.warnings) warn(line);
    MeshWall m;
    m.wall = static_cast<int>(walls_.size());
    m.file = s.file;
    m.axis_point = to_vec(s.axis_point);
    auto surface = std::make_shared<MeshSurface>(std::move(mesh));
    try {
      surface->set_flat_angle(s.flat_angle);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", ctx, e.what()));
    }
    m.turn_reach = surface->reach_from(m.axis_point);
    m.surface = std::move(surface);
    Wall<D> w;
    w.name = s.name;
    w.type = WallType::mesh;
    w.material = s.material;
    w.velocity = to_vec(s.velocity);
    w.angular_velocity = s.angular_velocity;
    w.axis = axis.normalized();
    w.center = m.axis_point;
    walls_.push_back(w);
    meshes_.mesh_of_wall.resize(walls_.size(), -1);
    meshes_.mesh_of_wall.back() = static_cast<int>(meshes_.meshes.size());
    meshes_.meshes.push_back(std::move(m));
    mesh_grid_reach_ = 0;
    lists_valid_ = false;
    unprepare();
    return static_cast<int>(walls_.size() - 1);
  }
}

template <int D>
std::vector<MeshView> Simulation<D>::mesh_views() const {
  std::vector<MeshView> out;
  for (const auto& m : meshes_.meshes) {
    MeshView v;
    v.wall = m.wall;
    if constexpr (D == 3) {
      for (const auto& x : m.surface->vertices()) v.vertices.push_back(to_triple(m.to_scene(x)));
      v.triangles = m.surface->triangles();
    } else {  // the outline, its arcs in pieces of at most 5 degrees
      for (const auto& x : m.surface->outline()) v.vertices.push_back(to_triple(m.to_scene(x)));
      for (std::uint32_t k = 0; k + 1 < v.vertices.size(); ++k) v.lines.push_back({k, k + 1});
    }
    out.push_back(std::move(v));
  }
  return out;
}

template <int D>
void Simulation<D>::prepare_meshes() {
  meshes_.mesh_of_wall.resize(walls_.size(), -1);
  if (meshes_.empty()) return;
  double r_max = 0;
  for (double r : p_.radius) r_max = std::max(r_max, r);
  const double reach = std::max(r_max + skin_ + contact_reach_, 1e-300);
  // The grids answer any reach; their cells only suit one. Rebuilt when the
  // particles' reach is far from the one they were built for.
  if (mesh_grid_reach_ > 0 && reach <= 2 * mesh_grid_reach_ && reach >= 0.25 * mesh_grid_reach_)
    return;
  if (!(r_max > 0) && mesh_grid_reach_ > 0) return;
  // Polylines need no grid: a disk tests each segment's bounding circle.
  if constexpr (D == 3) {
    for (auto& m : meshes_.meshes) {
      auto surface = std::make_shared<MeshSurface>(*m.surface);
      surface->build_grid(r_max > 0 ? reach : 1.0);
      m.surface = std::move(surface);
    }
  }
  mesh_grid_reach_ = r_max > 0 ? reach : 0;
}

template <int D>
void Simulation<D>::resolve_meshes() {
  for_each_model([&](auto index) {
    constexpr int I = decltype(index)::value;
    auto& wb = std::get<I>(wall_buckets_);
    if (wb.size())
      resolve_mesh_contacts(wb, p_, walls_, meshes_, contact_reach_, thread_count(), &mesh_tested_);
  });
}

namespace {
// A mesh's shape as the scene placed it (vertices and triangles): a restart whose
// scene read another file (edited since) would run the checkpoint's state in it.
std::int64_t shape_digest(const MeshSurface& surface) {
  Fnv1a digest;
  for (const auto& v : surface.vertices()) digest.add(v.data(), 3 * sizeof(double));
  for (const auto& t : surface.triangles()) digest.add(t.data(), sizeof t);
  return static_cast<std::int64_t>(digest.value() >> 1);  // >= 0 as a signed integer
}
// A polyline's (2D): its points, each segment's ends and arc radius, closed or not.
std::int64_t shape_digest(const PolylineSurface& surface) {
  Fnv1a digest;
  for (const auto& v : surface.points()) digest.add(v.data(), 2 * sizeof(double));
  for (std::size_t s = 0; s < surface.segment_count(); ++s) {
    const auto ends = surface.ends(s);
    const double radius = surface.arc_radius(s);
    digest.add(ends.data(), sizeof ends);
    digest.add(&radius, sizeof radius);
  }
  const bool closed = surface.closed();
  digest.add(&closed, sizeof closed);
  return static_cast<std::int64_t>(digest.value() >> 1);
}
}  // namespace

template <int D>
void Simulation<D>::save_meshes(StateBlob& s) const {
  std::vector<double> pose;
  std::vector<std::int64_t> shapes;
  for (const auto& m : meshes_.meshes) {
    pose.insert(pose.end(), {m.offset.x(), m.offset.y(), D == 3 ? m.offset[D - 1] : 0.0, m.angle});
    shapes.push_back(shape_digest(*m.surface));
  }
  s.doubles["meshes.pose"] = pose;
  s.integers["meshes.shape"] = shapes;
}

template <int D>
void Simulation<D>::load_meshes(const StateBlob& s) {
  const auto& pose = s.d("meshes.pose");
  if (pose.size() != 4 * meshes_.meshes.size())
    throw InputError(fmt::format(
        "checkpoint: 'meshes.pose' has {} values, expected 4 for each of the scene's {} mesh walls",
        pose.size(), meshes_.meshes.size()));
  for (double x : pose)
    if (!std::isfinite(x))
      throw InputError(fmt::format("checkpoint: 'meshes.pose' holds {}: not a pose", x));
  const auto& shapes = s.i("meshes.shape");
  if (shapes.size() != meshes_.meshes.size())
    throw InputError(fmt::format(
        "checkpoint: 'meshes.shape' has {} values, expected one for each of the scene's {} mesh "
        "walls",
        shapes.size(), meshes_.meshes.size()));
  for (std::size_t k = 0; k < meshes_.meshes.size(); ++k)
    if (shapes[k] != shape_digest(*meshes_.meshes[k].surface))
      throw InputError(fmt::format(
          "checkpoint: 'meshes.shape': the mesh wall '{}' is not the mesh the checkpoint was "
          "written with (its file, or how the scene places it, changed since)",
          walls_[meshes_.meshes[k].wall].name));
  for (std::size_t k = 0; k < meshes_.meshes.size(); ++k) {
    auto& m = meshes_.meshes[k];
    for (int d = 0; d < D; ++d) m.offset[d] = pose[4 * k + d];
    m.set_angle(pose[4 * k + 3], walls_[m.wall].axis);
    walls_[m.wall].center = m.axis_point_in_scene();
    walls_[m.wall].point = m.offset;
  }
  prepare_meshes();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
