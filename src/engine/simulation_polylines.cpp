// Polyline walls in the engine (2D): declaring one from its points and arcs.
// Everything after that (grids, contacts, motion, checkpoints, output) is the
// mesh walls' (simulation_meshes.cpp), which MeshSet<2> serves with
// PolylineSurface.
#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/plain_name.hpp"
#include "engine/simulation.hpp"

namespace granule {

template <int D>
int Simulation<D>::add_polyline_wall(const PolylineWallSpec& s) {
  const std::string ctx = fmt::format("wall_polyline '{}'", s.name);
  if constexpr (D == 3) {
    throw InputError(fmt::format(
        "{}: polyline walls are drawn in the plane, for 2D scenes; a 3D scene reads its shapes "
        "from CAD files with sim:wall_mesh",
        ctx));
  } else {
    check_plain_name(s.name, "wall_polyline");
    for (const auto& w : walls_)
      if (w.name == s.name) throw InputError(fmt::format("wall '{}' is declared twice", s.name));
    if (s.material < 0 || s.material >= static_cast<int>(materials_.size()))
      throw InputError(fmt::format("{}: unknown material", ctx));
    if (!finite3(s.velocity)) throw InputError(fmt::format("{}: velocity must be finite", ctx));
    if (!std::isfinite(s.angular_velocity))
      throw InputError(fmt::format("{}: angular_velocity must be finite", ctx));
    if (!finite3(s.axis_point)) throw InputError(fmt::format("{}: axis_point must be finite", ctx));
    if (s.solid && !s.closed)
      throw InputError(fmt::format(
          "{}: solid = true needs closed = true (only a closed polyline encloses a body)", ctx));
    Polyline line;
    line.closed = s.closed;
    for (const auto& x : s.points) line.points.emplace_back(x[0], x[1]);
    const std::size_t n = line.points.size();
    const std::size_t segments = n < 2 ? 0 : s.closed ? n : n - 1;
    line.radius.assign(segments, 0.0);
    for (std::size_t k = 0; k < s.arcs.size(); ++k) {
      const auto& arc = s.arcs[k];
      if (arc.segment < 1 || arc.segment > static_cast<std::int64_t>(segments))
        throw InputError(fmt::format(
            "{}: arcs[{}].segment = {} is out of range: the polyline has {} segments (1 to {}; "
            "segment k joins points k and k + 1{})",
            ctx, k + 1, arc.segment, segments, segments, s.closed ? ", the last closes it" : ""));
      if (!std::isfinite(arc.radius) || arc.radius == 0)
        throw InputError(
            fmt::format("{}: arcs[{}].radius = {}: must be a finite non-zero number (signed, m)",
                        ctx, k + 1, arc.radius));
      double& slot = line.radius[static_cast<std::size_t>(arc.segment - 1)];
      if (slot != 0)
        throw InputError(
            fmt::format("{}: arcs[{}]: segment {} has an arc already", ctx, k + 1, arc.segment));
      slot = arc.radius;
    }
    std::shared_ptr<const PolylineSurface> surface;
    try {
      surface = std::make_shared<PolylineSurface>(std::move(line));
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", ctx, e.what()));
    }
    PolylineWall m;
    m.wall = static_cast<int>(walls_.size());
    m.axis_point = to_vec(s.axis_point);
    m.turn_reach = surface->reach_from(m.axis_point);
    m.solid = s.solid;
    m.surface = std::move(surface);
    Wall<D> w;
    w.name = s.name;
    w.type = WallType::polyline;
    w.material = s.material;
    w.velocity = to_vec(s.velocity);
    w.angular_velocity = s.angular_velocity;
    w.center = m.axis_point;
    walls_.push_back(w);
    meshes_.mesh_of_wall.resize(walls_.size(), -1);
    meshes_.mesh_of_wall.back() = static_cast<int>(meshes_.meshes.size());
    meshes_.meshes.push_back(std::move(m));
    lists_valid_ = false;
    unprepare();
    return static_cast<int>(walls_.size() - 1);
  }
}

template <int D>
PolylineWallSpec Simulation<D>::polyline_wall(int w) const {
  const Wall<D>& x = walls_.at(static_cast<std::size_t>(w));
  if (x.type != WallType::polyline)
    throw InputError(fmt::format("wall '{}' is not a polyline", x.name));
  PolylineWallSpec s;
  s.name = x.name;
  s.material = x.material;
  s.velocity = to_triple(x.velocity);
  s.angular_velocity = x.angular_velocity;
  if constexpr (D == 2) {
    const PolylineWall& m = *meshes_.of_wall(static_cast<std::size_t>(w));
    s.axis_point = to_triple(m.axis_point);
    s.closed = m.surface->closed();
    s.solid = m.solid;
    for (const auto& p : m.surface->points()) s.points.push_back({p.x(), p.y()});
    for (std::size_t k = 0; k < m.surface->segment_count(); ++k)
      if (m.surface->arc_radius(k) != 0)
        s.arcs.push_back({static_cast<std::int64_t>(k + 1), m.surface->arc_radius(k)});
  }
  return s;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace granule
