#pragma once
// Triangle meshes from files (STL, OBJ, PLY, DAE, anything assimp reads). Part of porter::core_io.

#include <cstddef>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "porter/core/geometry.hpp"

namespace porter {

/// Limits of a mesh file (docs/hardening.md). Checked before assimp allocates (file size, a PLY
/// header's element counts against the bytes that follow it, an OFF header's counts, an OBJ
/// file's vertex, face and corner lines) and before assimp's post-processing runs (vertex,
/// face and post-triangulation counts, every face index below the vertex count).
inline constexpr std::uintmax_t kMeshMaxFileBytes = std::uintmax_t{256} << 20;
inline constexpr std::size_t kMeshMaxVertices = 6'000'000;
inline constexpr std::size_t kMeshMaxFaces = 2'000'000;
/// Largest |coordinate| after scaling, m (the same 10 km as a scene's numbers).
inline constexpr double kMeshMaxCoordinate_m = 1e4;

/// Loads every mesh in the file into one triangle mesh in the file's root frame (node
/// transforms applied), scales it per axis, merges duplicate vertices and reports closedness.
/// DAE files are converted from their declared unit to metres by assimp.
/// Throws LoadError (file, "", reason) when the file is missing or not a regular file,
/// unreadable, beyond a limit above, has a face index out of range, or has no triangles.
MeshPtr load_mesh(const std::string& path, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

}  // namespace porter
