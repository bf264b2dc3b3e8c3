#include "io/mesh_file.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/errors.hpp"
#include "io/rank_files.hpp"

namespace granule::io {

std::vector<std::string> MeshFileReport::warnings(const std::string& path) const {
  std::vector<std::string> out;
  if (degenerate_removed)
    out.push_back(fmt::format("mesh '{}': {} degenerate triangle(s) of {} removed (no area)", path,
                              degenerate_removed, triangles_read));
  if (open_edges)
    out.push_back(
        fmt::format("mesh '{}': {} open edge(s) (the surface is not closed, or has seams or "
                    "T-junctions, which act as joined; harmless for a wall)",
                    path, open_edges));
  if (non_manifold_edges)
    out.push_back(fmt::format(
        "mesh '{}': {} non-manifold edge(s) (three triangles or more on one edge; harmless for "
        "a wall)",
        path, non_manifold_edges));
  return out;
}

Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double radians) {
  return Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
}

Eigen::Matrix3d rotation_xyz(double rx, double ry, double rz) {
  using A = Eigen::AngleAxisd;
  return (A(rz, Eigen::Vector3d::UnitZ()) * A(ry, Eigen::Vector3d::UnitY()) *
          A(rx, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

namespace {
void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, TriangleMesh& out,
             const std::string& path) {
  const aiMatrix4x4 to_scene = parent * node->mTransformation;
  for (unsigned m = 0; m < node->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[m]];
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      // As read, before the file's node transform spreads one NaN over all three.
      const aiVector3D& read = mesh->mVertices[v];
      if (!std::isfinite(read.x) || !std::isfinite(read.y) || !std::isfinite(read.z))
        throw InputError(
            fmt::format("mesh file '{}': vertex {} (counted from 1, as read) is not "
                        "finite ({} {} {})",
                        path, out.vertices.size() + 1, read.x, read.y, read.z));
      const aiVector3D x = to_scene * read;
      out.vertices.emplace_back(x.x, x.y, x.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines: not surfaces
      out.triangles.push_back(
          {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    collect(scene, node->mChildren[c], to_scene, out, path);
}

// A face's vector area: half the sum of the cross products of a fan from its
// first corner (exact for any origin, without the cancellation of coordinates
// far from the file's); its length is the area of a planar polygon.
Eigen::Vector3d vector_area(const aiMesh* mesh, const aiFace& face) {
  auto corner = [&](unsigned c) {
    const aiVector3D& x = mesh->mVertices[face.mIndices[c]];
    const aiVector3D& o = mesh->mVertices[face.mIndices[0]];
    return Eigen::Vector3d(double(x.x) - o.x, double(x.y) - o.y, double(x.z) - o.z);
  };
  Eigen::Vector3d twice = Eigen::Vector3d::Zero();
  for (unsigned c = 1; c + 1 < face.mNumIndices; ++c) twice += corner(c).cross(corner(c + 1));
  return 0.5 * twice;
}

// Each mesh's faces as read, before triangulation: corners and vector area.
struct Polygon {
  unsigned corners;
  Eigen::Vector3d area;
};
std::vector<std::vector<Polygon>> polygons_of(const aiScene* scene) {
  std::vector<std::vector<Polygon>> out(scene->mNumMeshes);
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f)
      out[m].push_back({mesh->mFaces[f].mNumIndices, vector_area(mesh, mesh->mFaces[f])});
  }
  return out;
}

// assimp cuts some non-convex polygons into triangles that overlap one another
// and cover ground outside the polygon (an L-shaped hexagon: 4/3 of its area).
// A right cut's triangles all face the polygon's way and their areas along its
// normal add up to its vector area, warped or not; a wrong one's overlap or
// turn over and add up to more. assimp writes each polygon's triangles in
// turn, so they are found by count; where the counts do not match, a mesh's
// triangles are held to its polygons' summed area instead (to 1e-3: a warped
// polygon's triangles have a little more area than its vector area).
void check_cut(const aiScene* scene, const std::vector<std::vector<Polygon>>& polygons,
               const std::string& path) {
  for (unsigned m = 0; m < scene->mNumMeshes && m < polygons.size(); ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    std::size_t expected = 0;
    double polygons_area = 0;
    for (const Polygon& p : polygons[m]) {
      expected += p.corners >= 3 ? p.corners - 2 : 1;
      if (p.corners >= 3) polygons_area += p.area.norm();
    }
    if (!std::isfinite(polygons_area)) continue;  // a vertex that is not finite: refused by name
    auto refuse = [&](const std::string& which, double area, double covered) {
      throw InputError(fmt::format(
          "mesh file '{}': {} has an area of {:.6g} but the triangles it was cut into cover "
          "{:.6g}: the cut (assimp's) is wrong for a non-convex polygon; export the file with "
          "triangles only",
          path, which, area, covered));
    };
    if (mesh->mNumFaces != expected) {
      double covered = 0;
      for (unsigned f = 0; f < mesh->mNumFaces; ++f)
        if (mesh->mFaces[f].mNumIndices >= 3) covered += vector_area(mesh, mesh->mFaces[f]).norm();
      if (!(std::abs(covered - polygons_area) <= 1e-3 * polygons_area))
        refuse(fmt::format("mesh {} (its faces together)", m + 1), polygons_area, covered);
      continue;
    }
    unsigned f = 0;
    for (std::size_t k = 0; k < polygons[m].size(); ++k) {
      const Polygon& p = polygons[m][k];
      const unsigned pieces = p.corners >= 3 ? p.corners - 2 : 1;
      const double area = p.area.norm();
      if (p.corners > 3 && area > 0) {
        const Eigen::Vector3d normal = p.area / area;
        double covered = 0;
        for (unsigned q = 0; q < pieces; ++q)
          covered += std::abs(vector_area(mesh, mesh->mFaces[f + q]).dot(normal));
        if (!(covered <= area * (1 + 1e-9)))
          refuse(fmt::format("face {} of mesh {} ({} corners)", k + 1, m + 1, p.corners), area,
                 covered);
      }
      f += pieces;
    }
  }
}
}  // namespace

void clean_mesh(TriangleMesh& mesh, MeshFileReport& report) {
  // Corners at exactly the same point are one vertex: STL stores every
  // triangle's corners apart, and the contact needs the triangles around each
  // edge and vertex.
  std::map<std::array<double, 3>, std::uint32_t> index_of;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto& x = mesh.vertices[v];
    auto [it, fresh] =
        index_of.try_emplace({x.x(), x.y(), x.z()}, static_cast<std::uint32_t>(kept.size()));
    if (fresh) kept.push_back(x);
    remap[v] = it->second;
  }
  report.vertices_merged = mesh.vertices.size() - kept.size();
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (auto t : mesh.triangles) {
    for (auto& c : t) c = remap[c];
    const Eigen::Vector3d &a = kept[t[0]], &b = kept[t[1]], &c = kept[t[2]];
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // Area below 1e-12 of the longest edge squared: a sliver with no normal to speak of.
    const bool degenerate = t[0] == t[1] || t[1] == t[2] || t[2] == t[0] ||
                            !((b - a).cross(c - a).norm() > 1e-12 * longest);
    if (degenerate)
      ++report.degenerate_removed;
    else
      triangles.push_back(t);
  }
  mesh.vertices = std::move(kept);
  mesh.triangles = std::move(triangles);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      ++edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  report.open_edges = report.non_manifold_edges = 0;
  for (const auto& [edge, uses] : edge_uses) {
    if (uses == 1) ++report.open_edges;
    if (uses > 2) ++report.non_manifold_edges;
  }
}

TriangleMesh read_mesh_file(const std::string& path, const MeshTransform& transform,
                            MeshFileReport& report) {
  // Messages name the file as the scene did; the bytes may be this rank's copy.
  const std::string file = readable_path(path);
  if (!(transform.scale > 0) || !std::isfinite(transform.scale))
    throw InputError(fmt::format("mesh '{}': scale must be a finite number > 0 (got {})", path,
                                 transform.scale));
  if (!transform.translation.allFinite() || !transform.rotation.allFinite())
    throw InputError(fmt::format("mesh '{}': translate and rotate must be finite", path));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError(fmt::format("mesh file '{}' does not exist or is not a file", path));
  if (!std::ifstream(file).good())
    throw InputError(fmt::format("mesh file '{}' cannot be read (permissions?)", path));
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file, 0);
  if (!scene || !scene->mRootNode)
    throw InputError(
        fmt::format("mesh file '{}' cannot be read: {}", path, importer.GetErrorString()));
  // Triangulate: OBJ faces may be quads or polygons. Nothing else: corners are
  // joined below by position alone (assimp's join also compares normals).
  const auto polygons = polygons_of(scene);
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (!scene || !scene->mRootNode)
    throw InputError(
        fmt::format("mesh file '{}' cannot be read: {}", path, importer.GetErrorString()));
  check_cut(scene, polygons, path);
  TriangleMesh mesh;
  collect(scene, scene->mRootNode, aiMatrix4x4(), mesh, path);
  report = MeshFileReport{};
  report.triangles_read = mesh.triangles.size();
  // Far beyond any scene, and where the squares of lengths (areas, distances)
  // overflow: a slip of scale or units.
  constexpr double farthest = 1e100;  // m
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    Eigen::Vector3d& x = mesh.vertices[v];
    x = transform.rotation * (transform.scale * x) + transform.translation;
    if (!(x.cwiseAbs().maxCoeff() < farthest))
      throw InputError(fmt::format(
          "mesh '{}': vertex {} lies at ({:g} {:g} {:g}) m after scale = {:g}, beyond {:g} m: is "
          "the scale right (a file in mm needs scale = 1e-3)?",
          path, v + 1, x.x(), x.y(), x.z(), transform.scale, farthest));
  }
  clean_mesh(mesh, report);
  if (mesh.triangles.empty())
    throw InputError(
        fmt::format("mesh file '{}' has no triangles with an area ({} read, {} degenerate)", path,
                    report.triangles_read, report.degenerate_removed));
  // Only the vertices the triangles use.
  std::vector<std::int64_t> used(mesh.vertices.size(), -1);
  std::vector<Eigen::Vector3d> vertices;
  for (auto& t : mesh.triangles)
    for (auto& c : t) {
      if (used[c] < 0)
        used[c] = static_cast<std::int64_t>(vertices.size()), vertices.push_back(mesh.vertices[c]);
      c = static_cast<std::uint32_t>(used[c]);
    }
  mesh.vertices = std::move(vertices);
  return mesh;
}

}  // namespace granule::io
