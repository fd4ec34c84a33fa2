#pragma once
// Test-only reference CollisionChecker: slow and exact against the voxel map.
//
// A link shape, placed in W by forward kinematics, collides when shape_intersects_aabb() holds
// for an occupied voxel's box, or when its bounds leave the map's horizontal extent; arm links
// and the payload (links 1..7) also collide when they reach below the ground (z < -1e-6; the
// base's wheels rest on it). Self-collision is NOT covered (geometry.hpp has no shape/shape
// test); the kernel checker's own tests cover it. check_motion samples the straight line in
// [x, y, yaw, q] so that no point of the robot moves more than step_m between samples (bound:
// |dxy| + R_yaw |dyaw| + sum_j R_j |dq_j|, with R_j a configuration-independent bound on the
// distance of any point moved by joint j from its axis, from the model's fixed link offsets
// and bounding spheres).

#include <memory>

#include "porter/core/kinematics.hpp"
#include "porter/core/occupancy_grid.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::test {

class ExactCollisionChecker : public planner::CollisionChecker {
 public:
  explicit ExactCollisionChecker(const RobotModel& model, double step_m = 0.01);

  void set_map(const OccupancyGrid& occupancy_W) override { grid_ = occupancy_W; }
  planner::CollisionResult check(const RobotConfiguration& config) const override;
  planner::CollisionResult check_base(const BasePose& base) const override;
  planner::CollisionResult check_motion(const RobotConfiguration& from, const RobotConfiguration& to) const override;
  planner::CollisionResult check_trajectory(const Trajectory& trajectory) const override;
  /// Self-collision is not covered (see above): always free.
  planner::CollisionResult check_trajectory_self(const Trajectory&) const override { return {}; }
  /// Exact: no inflation.
  double inflation_bound_m(int) const override { return 0.0; }
  std::string name() const override { return "exact-test"; }

  /// Environment/ground test of one link placed at T_W_L.
  bool link_collides(int link, const Eigen::Isometry3d& T_W_L) const;

 private:
  const RobotModel& model_;
  double step_m_;
  double reach_yaw_m_ = 0.0;
  JointVector reach_m_ = JointVector::Zero();
  OccupancyGrid grid_;
};

}  // namespace porter::test
