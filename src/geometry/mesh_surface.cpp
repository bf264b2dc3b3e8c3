#include "geometry/mesh_surface.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "core/errors.hpp"

namespace granule {

namespace {
// Compressed rows: for each key in [0, n), the values pushed for it.
void compress(std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& kv,
              std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& values) {
  start.assign(n + 1, 0);
  for (auto& [k, v] : kv) ++start[k + 1];
  for (std::size_t k = 0; k < n; ++k) start[k + 1] += start[k];
  values.resize(kv.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (auto& [k, v] : kv) values[fill[k]++] = v;
}
}  // namespace

MeshSurface::MeshSurface(Triangles mesh)
    : x_(std::move(mesh.vertices)), tri_(std::move(mesh.triangles)) {
  if (tri_.empty()) throw InputError("a mesh wall needs at least one triangle");
  set_flat_angle(default_flat_angle);
  normal_.resize(tri_.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edge_of;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_tri, vertex_tri;
  tri_edge_.resize(tri_.size());
  for (std::uint32_t t = 0; t < tri_.size(); ++t) {
    const auto& c = tri_[t];
    normal_[t] = (x_[c[1]] - x_[c[0]]).cross(x_[c[2]] - x_[c[0]]).normalized();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(c[k], c[(k + 1) % 3]), b = std::max(c[k], c[(k + 1) % 3]);
      auto [it, fresh] =
          edge_of.try_emplace({a, b}, static_cast<std::uint32_t>(edge_vertex_.size()));
      if (fresh) edge_vertex_.push_back({a, b});
      tri_edge_[t][k] = it->second;
      edge_tri.push_back({it->second, t});
      vertex_tri.push_back({c[k], t});
    }
  }
  compress(edge_vertex_.size(), edge_tri, edge_start_, edge_tris_);
  compress(x_.size(), vertex_tri, vertex_start_, vertex_tris_);
  lo_ = hi_ = x_[0];
  for (const auto& v : x_) lo_ = lo_.cwiseMin(v), hi_ = hi_.cwiseMax(v);
  seam_ = 1e-6 * (hi_ - lo_).norm();
}

double MeshSurface::reach_from(const Eigen::Vector3d& point) const {
  double most = 0;
  for (const auto& v : x_) most = std::max(most, (v - point).norm());
  return most;
}

// Closest point of a triangle to x by the Voronoi regions of its corners,
// edges and face (as in Ericson, Real-Time Collision Detection, 5.1.5). An
// edge's point is computed along the edge from its lower vertex index, and a
// face's by projection on the face's plane, so the triangles that share a
// feature find bit-identical points there.
MeshHit MeshSurface::closest(std::uint32_t t, const Eigen::Vector3d& x) const {
  const auto& c = tri_[t];
  const Eigen::Vector3d &a = x_[c[0]], &b = x_[c[1]], &cc = x_[c[2]];
  MeshHit h;
  h.triangle = t;
  auto at_vertex = [&](std::uint32_t v) {
    h.feature = MeshFeature::vertex;
    h.element = v;
    h.point = x_[v];
  };
  auto at_edge = [&](int k) {
    const auto& e = edge_vertex_[tri_edge_[t][k]];
    const Eigen::Vector3d &p = x_[e[0]], &q = x_[e[1]];
    const Eigen::Vector3d pq = q - p;
    const double s = (x - p).dot(pq) / pq.squaredNorm();
    if (!(s > 0)) return at_vertex(e[0]);
    if (!(s < 1)) return at_vertex(e[1]);
    h.feature = MeshFeature::edge;
    h.element = tri_edge_[t][k];
    h.point = p + s * pq;
  };
  const Eigen::Vector3d ab = b - a, ac = cc - a, ax = x - a;
  const double d1 = ab.dot(ax), d2 = ac.dot(ax);
  const Eigen::Vector3d bx = x - b;
  const double d3 = ab.dot(bx), d4 = ac.dot(bx);
  const Eigen::Vector3d cx = x - cc;
  const double d5 = ab.dot(cx), d6 = ac.dot(cx);
  const double va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
  if (d1 <= 0 && d2 <= 0) {
    at_vertex(c[0]);
  } else if (d3 >= 0 && d4 <= d3) {
    at_vertex(c[1]);
  } else if (d6 >= 0 && d5 <= d6) {
    at_vertex(c[2]);
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    at_edge(0);  // a-b
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    at_edge(2);  // c-a
  } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    at_edge(1);  // b-c
  } else {
    const Eigen::Vector3d& n = normal_[t];
    const double above = ax.dot(n);
    h.feature = MeshFeature::face;
    h.element = t;
    h.point = x - above * n;
    h.distance = std::abs(above);
    h.normal = above < 0 ? Eigen::Vector3d(-n) : n;
    return h;
  }
  const Eigen::Vector3d away = x - h.point;
  h.distance = away.norm();
  if (h.distance > 0) {
    h.normal = away / h.distance;
  } else {  // the centre on the edge itself: any normal of the triangle's will do
    h.normal = normal_[t];
  }
  return h;
}

void MeshSurface::set_flat_angle(double degrees) {
  if (!(degrees >= 0 && degrees < 90))
    throw InputError(fmt::format("flat_angle must be in [0, 90) degrees, got {}", degrees));
  flat_angle_ = degrees;
  flat_cos_ = degrees > 0 ? std::cos(degrees * M_PI / 180) : 2.0;
}

void MeshSurface::build_grid(double reach) {
  if (!(reach > 0) || !std::isfinite(reach))
    throw InputError("mesh grid: the query reach must be a finite number > 0");
  const Eigen::Vector3d size = hi_ - lo_;
  double cell = 2 * reach;
  // Cells no smaller than the triangles' mean edge (each triangle in a few
  // cells), and no more than 2^22 of them.
  double edges = 0;
  for (const auto& e : edge_vertex_) edges += (x_[e[1]] - x_[e[0]]).norm();
  cell = std::max(cell, edges / static_cast<double>(edge_vertex_.size()));
  auto count = [&](double h) {
    double total = 1;
    for (int d = 0; d < 3; ++d) total *= std::floor(size[d] / h) + 1;
    return total;
  };
  while (count(cell) > double(1 << 22)) cell *= 1.25;
  grid_ = TriangleGrid{};
  grid_.cell = cell;
  grid_.origin = lo_;
  for (int d = 0; d < 3; ++d)
    grid_.n[d] = static_cast<std::int64_t>(std::floor(size[d] / cell)) + 1;
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_tri;
  for (std::uint32_t t = 0; t < tri_.size(); ++t) {
    Eigen::Vector3d tlo = x_[tri_[t][0]], thi = tlo;
    for (int k = 1; k < 3; ++k)
      tlo = tlo.cwiseMin(x_[tri_[t][k]]), thi = thi.cwiseMax(x_[tri_[t][k]]);
    std::array<std::int64_t, 3> a, b;
    for (int d = 0; d < 3; ++d) {
      a[d] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((tlo[d] - lo_[d]) / cell)), 0, grid_.n[d] - 1);
      b[d] = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((thi[d] - lo_[d]) / cell)), 0, grid_.n[d] - 1);
    }
    for (std::int64_t i = a[0]; i <= b[0]; ++i)
      for (std::int64_t j = a[1]; j <= b[1]; ++j)
        for (std::int64_t k = a[2]; k <= b[2]; ++k) {
          const Eigen::Vector3d centre = lo_ + cell * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
          // (with slack for the rounding of cells far larger than the triangle)
          if (closest(t, centre).distance > half_diagonal * (1 + 1e-9)) continue;
          cell_tri.push_back(
              {static_cast<std::uint32_t>((i * grid_.n[1] + j) * grid_.n[2] + k), t});
        }
  }
  compress(static_cast<std::size_t>(grid_.n[0] * grid_.n[1] * grid_.n[2]), cell_tri, grid_.start,
           grid_.items);
}

void MeshSurface::candidates(const Eigen::Vector3d& x, double within,
                             std::vector<std::uint32_t>& out) const {
  out.clear();
  std::array<std::int64_t, 3> a, b;
  for (int d = 0; d < 3; ++d) {
    const double lo = std::floor((x[d] - within - grid_.origin[d]) / grid_.cell);
    const double hi = std::floor((x[d] + within - grid_.origin[d]) / grid_.cell);
    if (!(hi >= 0) || !(lo < static_cast<double>(grid_.n[d]))) return;  // outside the grid
    // Clamped before the conversion: a reach beyond the grid (a fast wall's) is no integer.
    a[d] = lo > 0 ? static_cast<std::int64_t>(lo) : 0;
    b[d] =
        hi < static_cast<double>(grid_.n[d] - 1) ? static_cast<std::int64_t>(hi) : grid_.n[d] - 1;
  }
  for (std::int64_t i = a[0]; i <= b[0]; ++i)
    for (std::int64_t j = a[1]; j <= b[1]; ++j)
      for (std::int64_t k = a[2]; k <= b[2]; ++k) {
        const std::size_t cell = static_cast<std::size_t>((i * grid_.n[1] + j) * grid_.n[2] + k);
        out.insert(out.end(), grid_.items.begin() + grid_.start[cell],
                   grid_.items.begin() + grid_.start[cell + 1]);
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool MeshSurface::near(const Eigen::Vector3d& x, double within) const {
  if (!grid_.built()) {  // before the scene is prepared (fills): every triangle
    for (std::uint32_t t = 0; t < tri_.size(); ++t)
      if (closest(t, x).distance < within) return true;
    return false;
  }
  thread_local std::vector<std::uint32_t> near_tris;
  candidates(x, within, near_tris);
  for (const std::uint32_t t : near_tris)
    if (closest(t, x).distance < within) return true;
  return false;
}

bool MeshSurface::shares(std::uint32_t t, const MeshHit& h) const {
  const bool edge = h.feature == MeshFeature::edge;
  const auto& start = edge ? edge_start_ : vertex_start_;
  const auto& around = edge ? edge_tris_ : vertex_tris_;
  return std::find(around.begin() + start[h.element], around.begin() + start[h.element + 1], t) !=
         around.begin() + start[h.element + 1];
}

// Near an edge's point, the other side of a seam or a T-junction runs along
// the edge: it passes within `touching` of the point and of the edge a little
// further one way or the other. A triangle that only comes near at a corner
// (the next rim of a hole, a notch) does not, and leaves the point its contact.
bool MeshSurface::touches(std::uint32_t t, const MeshHit& h, double touching) const {
  if (closest(t, h.point).distance > touching) return false;
  if (h.feature != MeshFeature::edge) return true;
  const auto& e = edge_vertex_[h.element];
  const Eigen::Vector3d &p = x_[e[0]], &q = x_[e[1]];
  const double length = (q - p).norm();
  const double at = (h.point - p).dot(q - p) / length;
  const double step = std::min(16 * touching, 0.5 * length);  // one way stays on the edge
  for (const double along : {at - step, at + step})
    if (along >= 0 && along <= length &&
        closest(t, p + (along / length) * (q - p)).distance <= touching)
      return true;
  return false;
}

int MeshSurface::contacts(const Eigen::Vector3d& x, double radius, double within, MeshHit* out,
                          std::int64_t* tested) const {
  thread_local std::vector<std::uint32_t> near_tris;
  thread_local std::vector<MeshHit> hits;
  if (!grid_.built()) throw std::logic_error("MeshSurface::contacts before build_grid");
  candidates(x, within, near_tris);
  if (tested) *tested += static_cast<std::int64_t>(near_tris.size());
  hits.clear();
  for (const std::uint32_t t : near_tris) {
    MeshHit h = closest(t, x);
    if (h.distance < within) hits.push_back(h);
  }
  // Nearest first; ties by triangle index, so the owner of a shared point is
  // the same whatever the order the cells listed the triangles in.
  auto before = [](const MeshHit& p, const MeshHit& q) {
    return p.distance < q.distance || (p.distance == q.distance && p.triangle < q.triangle);
  };
  std::sort(hits.begin(), hits.end(), before);
  int count = 0;
  // Two closest points closer than this are one contact (the same point found
  // by two triangles of a flat patch, rounded differently).
  const double same = 1e-6 * radius;
  // A surface passing this near an edge or corner point touches it: a crack
  // narrower than this, or a corner of a T-junction a rounding off the long
  // edge, is joined (a thousandth of the radius, far inside a contact's patch,
  // or the single-precision rounding of the mesh's size; at most a tenth of
  // the radius, at which a hole's rim holds distinct contacts).
  const double touching = std::min(0.1 * radius, std::max(1e-3 * radius, seam_));
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const MeshHit& h = hits[i];
    if (h.feature != MeshFeature::face) {
      // An edge or corner point belongs to every triangle that passes through
      // it: each of those is at least as near, and the first of them owns the
      // contact (if its closest point is elsewhere, this point is no minimum
      // at all). Those are the nearer hits: the triangles around the edge or
      // corner by the mesh's topology, and any other that touches the point
      // (an unjoined seam, a T-junction, the hole a removed sliver left).
      bool owned = false;
      for (std::size_t k = 0; k < i && !owned; ++k)
        owned = hits[k].triangle != h.triangle && shares(hits[k].triangle, h);
      for (std::size_t k = 0; k < i && !owned; ++k)
        owned = hits[k].triangle != h.triangle && touches(hits[k].triangle, h, touching);
      if (owned) continue;
    }
    // A point already found (two triangles of a flat patch), or the farther
    // contact of a shallow concave fold: the nearer one stands for both. Only
    // two faces' inner points make a fold: edges and corners are convex
    // features, each a contact of its own however alike their normals (a
    // sphere on the rim of a hole smaller than itself rests on all of them).
    bool repeated = false;
    for (int k = 0; k < count && !repeated; ++k)
      repeated = (out[k].point - h.point).norm() <= same ||
                 (h.feature == MeshFeature::face && out[k].feature == MeshFeature::face &&
                  out[k].normal.dot(h.normal) > flat_cos_);
    if (repeated) continue;
    out[count++] = h;
    if (count == max_hits) break;
  }
  return count;
}

}  // namespace granule
