#pragma once
// Bounding-sphere cover of the robot and its payload, the body model of the sphere baseline
// (REMANI / TOPAY, algorithms.md §2.2, §3; the paper's "bounding sphere cover").
//
// Each planning link's geometry (payload included in link 7) is voxelized in its own frame at
// cell_m; every cell that meets the geometry (shape_intersects_aabb) and has one of its 26
// neighbours that does not gets the sphere circumscribing the cell: centre at the cell centre, radius
// cell_m sqrt(3)/2. Those cells hold the whole surface, so every surface point is inside a sphere
// (interior cells add nothing: an obstacle outside the body reaches its inside only through the
// surface). The cover is conservative and inflates the body by up to cell_m sqrt(3) (10.4 cm at
// the default 6 cm): the feasible space a sphere model loses around a large payload.
//
// Frames and units: link frames Lj, metres. Pure functions; thread-safe.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::baselines {

struct SphereCoverSettings {
  /// Cell edge of the cover, m. > 0. Smaller cells inflate less and cost more spheres.
  double cell_m = 0.06;
};

struct LinkSpheres {
  std::vector<Eigen::Vector3d> centers_L;  ///< link frame
  double radius_m = 0.0;                   ///< the same for every sphere of the cover
};

using RobotSpheres = std::array<LinkSpheres, kNumLinks>;

RobotSpheres cover_robot(const RobotModel& model, const SphereCoverSettings& settings = {});
LinkSpheres cover_shapes(const std::vector<CollisionShape>& shapes_L, double cell_m);

}  // namespace porter::baselines
