#pragma once
// Triangle meshes from files (STL, OBJ, PLY, DAE, anything assimp reads). Part of porter::core_io.

#include <string>

#include <Eigen/Core>

#include "porter/core/geometry.hpp"

namespace porter {

/// Loads every mesh in the file into one triangle mesh in the file's root frame (node
/// transforms applied), scales it per axis, merges duplicate vertices and reports closedness.
/// DAE files are converted from their declared unit to metres by assimp.
/// Throws LoadError (file, "", reason) when the file is missing, unreadable, or has no triangles.
MeshPtr load_mesh(const std::string& path, const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

}  // namespace porter
