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
#include "ply_header.hpp"
#include "text_mesh_counts.hpp"

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


// Every mesh of an imported (not yet post-processed) scene: counts within the limits, vertex
// arrays present, every face index below its mesh's vertex count. assimp's post-processing
// steps index vertices with the face indices unchecked (an out-of-range index segfaulted).
std::string check_imported(const aiScene& scene) {
  if (scene.mNumMeshes > 0 && scene.mMeshes == nullptr) return "mesh list missing";
  std::size_t vertices = 0, faces = 0, triangles = 0;
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr) return "mesh " + std::to_string(m) + " missing";
    vertices += mesh->mNumVertices;
    faces += mesh->mNumFaces;
    if (vertices > kMeshMaxVertices)
      return "more than " + std::to_string(kMeshMaxVertices) + " vertices";
    if (faces > kMeshMaxFaces) return "more than " + std::to_string(kMeshMaxFaces) + " faces";
    if (mesh->mNumVertices > 0 && mesh->mVertices == nullptr) return "mesh " + std::to_string(m) + " has no vertex array";
    if (mesh->mNumFaces > 0 && mesh->mFaces == nullptr) return "mesh " + std::to_string(m) + " has no face array";
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices == 0 || face.mIndices == nullptr)
        return "face " + std::to_string(f) + " of mesh " + std::to_string(m) + " has no indices";
      // Triangulation turns an n-gon into n - 2 triangles: one face of 10^7 corners would
      // become 10^7 faces inside post-processing.
      triangles += face.mNumIndices >= 3 ? face.mNumIndices - 2 : 1;
      if (triangles > kMeshMaxFaces)
        return "more than " + std::to_string(kMeshMaxFaces) + " triangles once polygons are split";
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh->mNumVertices)
          return "face " + std::to_string(f) + " of mesh " + std::to_string(m) + " uses vertex " +
                 std::to_string(face.mIndices[k]) + " of " + std::to_string(mesh->mNumVertices);
    }
  }
  return {};
}

// The primitive types each mesh declares, recomputed from its faces. Importers can declare a
// type no face has (a PLY "polygon" mesh of triangles), and assimp's post-processing asserts on
// the declaration (TriangulateProcess: numOut != mNumFaces, an abort).
void fix_primitive_types(aiScene& scene) {
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    aiMesh& mesh = *scene.mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      types |= n == 1 ? aiPrimitiveType_POINT : n == 2 ? aiPrimitiveType_LINE : n == 3 ? aiPrimitiveType_TRIANGLE
                                                                                 : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
}

}  // namespace

MeshPtr load_mesh(const std::string& path, const Eigen::Vector3d& scale) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw LoadError(path, "", "mesh file not found");
  if (!std::filesystem::is_regular_file(path, ec)) throw LoadError(path, "", "mesh path is not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw LoadError(path, "", "cannot read the mesh file's size: " + ec.message());
  if (bytes > kMeshMaxFileBytes)
    throw LoadError(path, "", "mesh file of " + std::to_string(bytes) + " bytes exceeds the " +
                                  std::to_string(kMeshMaxFileBytes) + "-byte limit");
  if (!(scale.array() > 0.0).all() || !scale.allFinite())
    throw LoadError(path, "scale", "mesh scale must be positive in every axis");
  if (const std::string bad = detail::check_ply_header(path); !bad.empty()) throw LoadError(path, "", bad);
  if (const std::string bad = detail::check_text_mesh_counts(path); !bad.empty()) throw LoadError(path, "", bad);

  Assimp::Importer importer;
  // Point clouds and lines carry no volume; drop them so only triangles remain.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Import without post-processing, check indices and counts, then post-process.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (scene == nullptr)
    throw LoadError(path, "", std::string("unreadable mesh: ") + importer.GetErrorString());
  if (const std::string bad = check_imported(*scene); !bad.empty())
    throw LoadError(path, "", "malformed mesh: " + bad);
  // The importer owns the scene and post-processing rewrites it in place anyway.
  fix_primitive_types(const_cast<aiScene&>(*scene));
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                       aiProcess_SortByPType);
  if (scene == nullptr)
    throw LoadError(path, "", std::string("unreadable mesh: ") + importer.GetErrorString());
  if (const std::string bad = check_imported(*scene); !bad.empty())
    throw LoadError(path, "", "malformed mesh after triangulation: " + bad);

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
  for (const auto& v : raw) {
    if (!v.allFinite()) throw LoadError(path, "", "mesh has non-finite vertex coordinates");
    if (v.cwiseAbs().maxCoeff() > kMeshMaxCoordinate_m)
      throw LoadError(path, "", "mesh has a vertex beyond " + std::to_string(static_cast<int>(kMeshMaxCoordinate_m)) +
                                    " m after scaling");
  }

  auto mesh = std::make_shared<TriangleMesh>();
  mesh->source = path;
  weld_and_check(raw, *mesh);
  if (mesh->triangles.empty()) throw LoadError(path, "", "mesh has only degenerate triangles");
  return mesh;
}

}  // namespace porter
