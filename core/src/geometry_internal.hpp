#pragma once
// Helpers shared by the geometry_*.cpp files (not installed, not part of the public API).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"

namespace porter::detail {

/// std::visit helper: one lambda per alternative.
template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

/// Point in the shape's own frame from a point in its parent frame.
inline Eigen::Vector3d to_shape_frame(const CollisionShape& shape, const Eigen::Vector3d& p_parent) {
  const Eigen::Isometry3d& T = shape.T_parent_shape;
  return T.linear().transpose() * (p_parent - T.translation());
}

/// Generalized winding number of the mesh around p (mesh frame): ~+1 inside an outward-oriented
/// closed mesh, ~0 outside (Van Oosterom–Strackee solid angles, summed over triangles / 4π).
double mesh_winding_number(const TriangleMesh& mesh, const Eigen::Vector3d& p_mesh);

/// Unsigned distance from p (mesh frame) to the nearest triangle; +inf for an empty mesh.
double mesh_unsigned_distance(const TriangleMesh& mesh, const Eigen::Vector3d& p_mesh);

/// Inside test for a closed mesh by winding number (|w| > 1/2; orientation-agnostic).
inline bool mesh_winding_inside(const TriangleMesh& mesh, const Eigen::Vector3d& p_mesh) {
  const double w = mesh_winding_number(mesh, p_mesh);
  return w > 0.5 || w < -0.5;
}

}  // namespace porter::detail
