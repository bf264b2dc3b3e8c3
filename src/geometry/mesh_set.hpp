// The scene's surface walls: in 3D triangle meshes (each a rigid MeshSurface
// with a pose), in 2D polylines (each a rigid PolylineSurface with a pose). A mesh
// moves as a rigid body: it translates at its wall's velocity and turns at its
// angular velocity about an axis through a point that moves with it, so the
// pose is an offset and an angle, integrated each step, and the surface's
// velocity at a contact point q is v + omega axis x (q - axis point), the wall
// velocity of Eq. 3.10's slip. Contacts are found in the mesh's own frame (the
// particle brought into it), so the triangle grid is built once. The two
// dimensions share everything but the surface and the rotation's form.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/types.hpp"
#include "geometry/mesh_surface.hpp"
#include "geometry/polyline_surface.hpp"
#include "geometry/walls.hpp"

namespace granule {

struct MeshWall {
  static constexpr int max_hits = MeshSurface::max_hits;
  int wall = -1;  // its entry in the scene's walls (name, material, motion, reaction)
  std::string file;
  std::shared_ptr<const MeshSurface> surface;
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();  // in the mesh's frame
  // The pose: x_scene = R(angle) (x_mesh - axis_point) + axis_point + offset.
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double angle = 0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  double turn_reach = 0;  // the farthest vertex from the axis point (bounds a turn's travel)

  void set_angle(double a, const Eigen::Vector3d& axis) {
    angle = a;
    rotation = Eigen::AngleAxisd(a, axis).toRotationMatrix();
  }
  // Unturned meshes skip the rotation, so a mesh at rest is exactly where its
  // file put it.
  Eigen::Vector3d to_mesh(const Eigen::Vector3d& x) const {
    if (angle == 0) return x - offset;
    return rotation.transpose() * (x - axis_point - offset) + axis_point;
  }
  Eigen::Vector3d to_scene(const Eigen::Vector3d& x) const {
    if (angle == 0) return x + offset;
    return rotation * (x - axis_point) + axis_point + offset;
  }
  Eigen::Vector3d direction_to_scene(const Eigen::Vector3d& n) const {
    return angle == 0 ? n : Eigen::Vector3d(rotation * n);
  }
  Eigen::Vector3d axis_point_in_scene() const { return axis_point + offset; }
};

// A polyline wall (2D): the same pose, turning about z.
struct PolylineWall {
  static constexpr int max_hits = PolylineSurface::max_hits;
  int wall = -1;
  std::shared_ptr<const PolylineSurface> surface;
  Eigen::Vector2d axis_point = Eigen::Vector2d::Zero();  // in the polyline's frame
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  double angle = 0;
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();
  double turn_reach = 0;
  bool solid = false;  // a closed polyline whose inside is a body: fill{} places nothing there

  void set_angle(double a, const Eigen::Vector2d& /*axis: always z*/) {
    angle = a;
    rotation = Eigen::Rotation2Dd(a).toRotationMatrix();
  }
  Eigen::Vector2d to_mesh(const Eigen::Vector2d& x) const {
    if (angle == 0) return x - offset;
    return rotation.transpose() * (x - axis_point - offset) + axis_point;
  }
  Eigen::Vector2d to_scene(const Eigen::Vector2d& x) const {
    if (angle == 0) return x + offset;
    return rotation * (x - axis_point) + axis_point + offset;
  }
  Eigen::Vector2d direction_to_scene(const Eigen::Vector2d& n) const {
    return angle == 0 ? n : Eigen::Vector2d(rotation * n);
  }
  Eigen::Vector2d axis_point_in_scene() const { return axis_point + offset; }
};

template <int D>
struct MeshSet {
  using Shape = std::conditional_t<D == 3, MeshWall, PolylineWall>;
  std::vector<Shape> meshes;
  std::vector<int> mesh_of_wall;  // -1 for analytic walls

  bool empty() const { return meshes.empty(); }
  const Shape* of_wall(std::size_t w) const {
    if (w >= mesh_of_wall.size() || mesh_of_wall[w] < 0) return nullptr;
    return &meshes[mesh_of_wall[w]];
  }
  // Whether the particle at x lies within `within` of the mesh on wall w.
  bool near(std::size_t w, const Vec<D>& x, double within) const {
    const Shape* m = of_wall(w);
    return m && m->surface->near(m->to_mesh(x), within);
  }
  // Whether x lies inside the solid body of wall w (a 2D polyline declared
  // solid); always false in 3D.
  bool inside_solid(std::size_t w, const Vec<D>& x) const {
    if constexpr (D == 2) {
      const Shape* m = of_wall(w);
      return m && m->solid && m->surface->encloses(m->to_mesh(x));
    } else {
      (void)w, (void)x;
      return false;
    }
  }
  // Wall w's mesh as it stood a step ago, before move() moved it by dt (null for
  // an analytic wall).
  std::optional<Shape> before_step(std::size_t w, const Wall<D>& wall, double dt) const {
    const Shape* m = of_wall(w);
    if (!m) return std::nullopt;
    Shape before = *m;
    before.offset -= wall.velocity * dt;
    if (wall.angular_velocity != 0)
      before.set_angle(m->angle - wall.angular_velocity * dt, wall.axis);
    return before;
  }
  // That mesh (`before`, of wall `wall`) seen from a particle of `radius` at x:
  // false where no point of it lies within `within` of x; else, of its contacts
  // (every closest point within reach, not only the nearest: a blade can close
  // on a particle resting on a hub), the one that advanced furthest past its gap
  // over the step: its overlap with the particle (negative: the gap) and how far
  // that point moved along the normal towards x (m; negative: away), as the
  // mesh's motion moved it (a turn's too).
  static bool approach(const Shape& before, const Wall<D>& wall, const Vec<D>& x, double radius,
                       double within, double dt, double& overlap, double& advance) {
    std::conditional_t<D == 3, MeshHit, PolylineHit> hits[Shape::max_hits];
    const int count = before.surface->contacts(before.to_mesh(x), radius, within, hits);
    for (int k = 0; k < count; ++k) {
      const Vec<D> point = before.to_scene(hits[k].point);
      const Vec<D> normal = before.direction_to_scene(hits[k].normal);
      const Vec<D> lever = point - before.axis_point_in_scene();
      Vec<D> surface_velocity = wall.velocity;
      if constexpr (D == 3)
        surface_velocity += wall.angular_velocity * wall.axis.cross(lever);
      else
        surface_velocity += wall.angular_velocity * Vec<D>(-lever.y(), lever.x());
      const double a = surface_velocity.dot(normal) * dt, o = radius - hits[k].distance;
      if (k == 0 || a + o > advance + overlap) advance = a, overlap = o;
    }
    return count > 0;
  }
  // One step of rigid motion for every mesh; adds a bound on any vertex's
  // travel to its wall's moved_since_rebuild and sets it as the wall's `travel` (m).
  void move(std::vector<Wall<D>>& walls, double dt, std::vector<double>& travel_of) {
    for (auto& m : meshes) {
      Wall<D>& w = walls[m.wall];
      if (w.velocity.isZero() && w.angular_velocity == 0) continue;
      m.offset += w.velocity * dt;
      if (w.angular_velocity != 0) m.set_angle(m.angle + w.angular_velocity * dt, w.axis);
      w.center = m.axis_point_in_scene();
      w.point = m.offset;
      const double travel =
          (w.velocity * dt).stableNorm() + std::abs(w.angular_velocity * dt) * m.turn_reach;
      w.moved_since_rebuild[0] += travel;
      travel_of[static_cast<std::size_t>(m.wall)] = travel;
    }
  }
};

}  // namespace granule
