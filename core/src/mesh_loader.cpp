#include "porter/core/mesh_loader.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <tuple>
#include <unordered_map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "porter/core/load_error.hpp"

namespace porter {

namespace {

// Welds vertices closer than 1 nm (formats like STL repeat vertices per face), drops triangles
// that become degenerate, and decides closedness: every directed edge must meet its reverse
// exactly once.
void weld_and_check(const std::vector<Eigen::Vector3d>& raw, TriangleMesh& mesh) {
  constexpr double kQuantum = 1e-9;
  std::map<std::tuple<long long, long long, long long>, int> index_of;
  std::vector<int> remap(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const auto key = std::make_tuple(std::llround(raw[i].x() / kQuantum), std::llround(raw[i].y() / kQuantum),
                                     std::llround(raw[i].z() / kQuantum));
    auto [it, inserted] = index_of.emplace(key, static_cast<int>(mesh.vertices_m.size()));
    if (inserted) mesh.vertices_m.push_back(raw[i]);
    remap[i] = it->second;
  }
  std::vector<Eigen::Vector3i> tris;
  for (std::size_t t = 0; t + 2 < raw.size(); t += 3) {
    const Eigen::Vector3i tri(remap[t], remap[t + 1], remap[t + 2]);
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
    tris.push_back(tri);
  }
  mesh.triangles = std::move(tris);

  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  bool closed = !mesh.triangles.empty();
  for (const auto& [edge, count] : directed) {
    const auto rev = directed.find({edge.second, edge.first});
    if (count != 1 || rev == directed.end() || rev->second != 1) {
      closed = false;
      break;
    }
  }
  mesh.closed = closed;
}

}  // namespace

MeshPtr load_mesh(const std::string& path, const Eigen::Vector3d& scale) {
  if (!std::filesystem::exists(path)) throw LoadError(path, "", "mesh file not found");
  if (!(scale.array() > 0.0).all() || !scale.allFinite())
    throw LoadError(path, "scale", "mesh scale must be positive in every axis");

  Assimp::Importer importer;
  // Point clouds and lines carry no volume; drop them so only triangles remain.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr)
    throw LoadError(path, "", std::string("unreadable mesh: ") + importer.GetErrorString());

  std::vector<Eigen::Vector3d> raw;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (unsigned k = 0; k < 3; ++k) {
        const aiVector3D& v = mesh->mVertices[face.mIndices[k]];
        raw.emplace_back(v.x * scale.x(), v.y * scale.y(), v.z * scale.z());
      }
    }
  }
  if (raw.empty()) throw LoadError(path, "", "mesh has no triangles");
  for (const auto& v : raw)
    if (!v.allFinite()) throw LoadError(path, "", "mesh has non-finite vertex coordinates");

  auto mesh = std::make_shared<TriangleMesh>();
  mesh->source = path;
  weld_and_check(raw, *mesh);
  if (mesh->triangles.empty()) throw LoadError(path, "", "mesh has only degenerate triangles");
  return mesh;
}

}  // namespace porter
