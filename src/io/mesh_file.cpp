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
  // Triangulate: OBJ faces may be quads or polygons. Nothing else: corners are
  // joined below by position alone (assimp's join also compares normals).
  const aiScene* scene = importer.ReadFile(file, aiProcess_Triangulate);
  if (!scene || !scene->mRootNode)
    throw InputError(
        fmt::format("mesh file '{}' cannot be read: {}", path, importer.GetErrorString()));
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
