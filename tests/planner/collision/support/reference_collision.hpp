#pragma once
// Slow, obviously-correct references for the kernel collision checker (test-support library,
// shared with tests/bench). Nothing here is fast; everything is exact at voxel level.
//
// Environment (ReferenceEnvironment): a link collides when its exact geometry (placed by
// porter::forward_kinematics) intersects a "flagged" voxel of the map's lattice, where flagged
// means: in O_m (occupied voxel, or a voxel whose box is closer than the margin to an occupied
// voxel's box, by brute force over neighbours), outside the grid horizontally or above it, or,
// for links other than the base, below the ground z = 0. The link's voxels are computed with the
// exact scene voxelizer (porter::voxelize_shape, itself checked against shape_intersects_aabb).
//
// Self (ReferenceSelfCollision): exact overlap of the link geometries with FCL 0.7 (boxes,
// cylinders and spheres as FCL primitives, meshes as BVHs), for every pair the model's
// AllowedCollisionMatrix does not allow. FCL tests surfaces of meshes, so a mesh swallowed whole
// by another shape is not seen: the reference may miss such an overlap, never invent one.

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "porter/core/kinematics.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"

namespace porter::test {

class ReferenceEnvironment {
 public:
  ReferenceEnvironment(const OccupancyGrid& grid, double safety_margin_m);

  /// Voxel (grid index, any integers) flagged for the base (`base_link`) or for other links.
  bool flagged(const Eigen::Vector3i& idx, bool base_link) const;
  /// In O_m (false outside the grid).
  bool in_margin_set(const Eigen::Vector3i& idx) const;

  /// Whether link `link` collides at the configuration FK'd into ws.
  bool link_collides(const RobotModel& model, const KinematicsWorkspace& ws, int link) const;
  /// First colliding link (0..7) or -1.
  int first_colliding_link(const RobotModel& model, const RobotConfiguration& config) const;
  /// True when some flagged voxel's centre lies within distance_m of the link's exact
  /// geometry. A link within d of the flagged set has such a voxel for distance_m = d + h sqrt(3)/2
  /// (the centre is within half a diagonal of the voxel's nearest point), so this is the
  /// reference's test of the checker's false-positive bound.
  bool link_within(const RobotModel& model, const KinematicsWorkspace& ws, int link, double distance_m) const;

  const OccupancyGrid& grid() const { return grid_; }

 private:
  OccupancyGrid grid_;
  std::vector<bool> margin_set_;
  int ground_index_ = 0;
};

class ReferenceSelfCollision {
 public:
  explicit ReferenceSelfCollision(const RobotModel& model);
  ~ReferenceSelfCollision();
  ReferenceSelfCollision(const ReferenceSelfCollision&) = delete;
  ReferenceSelfCollision& operator=(const ReferenceSelfCollision&) = delete;

  /// Exact overlap of links a and b at joint values q.
  bool pair_collides(const JointVector& q_rad, int a, int b) const;
  /// Distance between links a and b (<= 0 when they overlap).
  double pair_distance(const JointVector& q_rad, int a, int b) const;
  /// First non-allowed pair found overlapping, {-1, -1} when none.
  std::array<int, 2> first_colliding_pair(const JointVector& q_rad) const;

 private:
  struct Impl;
  RobotModel model_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace porter::test
