// Mesh walls' contacts for the wall kernel. A particle near a mesh has
// MeshSurface::max_hits candidates in the wall bucket (its "parts", listed
// together); each step this pass finds the particle's contacts with the mesh
// (MeshSurface::contacts) and gives each to a part, so the wall kernel and
// every contact model treat it as any wall contact. A contact keeps its part
// while its normal turns continuously (it rolls from face to edge to the next
// triangle): the part whose last normal is closest to the new one takes it,
// so the tangential history follows the particle, not the triangle. A contact
// no part was following starts a fresh history. The same for a 2D scene's
// polylines (PolylineSurface), whose arcs also give the contact's R*.
#pragma once

#include <cstdint>
#include <vector>

#include "core/particles.hpp"
#include "geometry/finite_walls.hpp"
#include "geometry/mesh_set.hpp"
#include "kernel/buckets.hpp"

namespace granule {

// Parts whose last normals differ from a new contact's by more than 60 degrees
// do not follow it (a contact's normal turns by far less in one step).
constexpr double mesh_follow_cosine = 0.5;

template <int D, typename M>
void resolve_mesh_contacts(WallBucket<D, M>& b, const Particles<D>& p,
                           const std::vector<Wall<D>>& walls, const MeshSet<D>& meshes,
                           double reach, int threads, std::int64_t* tested_out = nullptr) {
  using Shape = typename MeshSet<D>::Shape;
  using Hit = std::conditional_t<D == 3, MeshHit, PolylineHit>;
  constexpr int K = Shape::max_hits;
  const std::int64_t n = static_cast<std::int64_t>(b.size());
  b.touch.resize(b.size());
  std::int64_t tested = 0;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1) \
    reduction(+ : tested)
  for (std::int64_t k0 = 0; k0 < n; ++k0) {
    if (b.part[k0] != 0) continue;  // a group starts at its part 0
    const Shape* m = meshes.of_wall(b.wall[k0]);
    if (!m) continue;
    const std::uint32_t i = b.particle[k0];
    const double r = p.radius[i];
    Hit hit[K];
    int found = m->surface->contacts(m->to_mesh(p.position[i]), r, r + reach, hit, &tested);
    if constexpr (D == 2) {
      // A disk whose centre got inside a solid polyline (a hard impact carried it over
      // the line, as an overlapping fill's first steps can) is pushed back out through
      // the nearest point of the chain, as an analytic cylinder pushes it out from its
      // axis: one contact, its normal outward, its overlap r + the centre's depth. A
      // chain's contacts alone would push it on inwards once the centre crossed.
      if (m->solid && m->surface->encloses(m->to_mesh(p.position[i]))) {
        hit[0] = m->surface->nearest(m->to_mesh(p.position[i]));
        hit[0].normal = -hit[0].normal;
        hit[0].distance = -hit[0].distance;
        hit[0].curvature_radius = 0;  // flat: the push-out's stiffness no arc's R* sets
        found = 1;
      }
    }
    const Wall<D>& w = walls[b.wall[k0]];
    bool taken[K] = {};
    int part_of[K];
    for (int h = 0; h < found; ++h) {
      hit[h].normal = m->direction_to_scene(hit[h].normal);
      int best = -1;
      double best_cos = mesh_follow_cosine;
      for (int j = 0; j < K; ++j) {
        if (taken[j]) continue;
        const double c = b.part_normal[k0 + j].dot(hit[h].normal);
        if (c > best_cos) best = j, best_cos = c;
      }
      if (best < 0) {  // a new contact: the first part not following one
        for (int j = 0; j < K && best < 0; ++j)
          if (!taken[j] && b.part_normal[k0 + j].isZero()) best = j;
        for (int j = 0; j < K && best < 0; ++j)
          if (!taken[j]) best = j;
        b.history[k0 + best] = typename WallBucket<D, M>::History{};
      }
      taken[best] = true;
      part_of[h] = best;
    }
    for (int j = 0; j < K; ++j) {
      b.touch[k0 + j] = WallTouch<D>{};
      if (!taken[j]) b.part_normal[k0 + j].setZero();
    }
    for (int h = 0; h < found; ++h) {
      const std::size_t k = k0 + part_of[h];
      WallTouch<D>& t = b.touch[k];
      const Vec<D> q = m->to_scene(hit[h].point);
      t.normal = hit[h].normal;
      t.overlap = r - hit[h].distance;
      t.lever = q - m->axis_point_in_scene();
      if constexpr (D == 3) {
        t.surface_velocity = w.velocity + w.angular_velocity * w.axis.cross(t.lever);
        t.effective_radius = r;  // flat faces; edges and corners as faces
      } else {
        t.surface_velocity = w.velocity + w.angular_velocity * Vec<D>(-t.lever.y(), t.lever.x());
        t.effective_radius = effective_radius_against(r, hit[h].curvature_radius, hit[h].concave);
      }
      b.part_normal[k] = t.normal;
    }
  }
  if (tested_out) *tested_out += tested;
}

}  // namespace granule
