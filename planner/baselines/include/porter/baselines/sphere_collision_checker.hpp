#pragma once
// SphereCollisionChecker: the collision model of the sphere baseline ("spheres", REMANI / TOPAY
// style): the robot and its payload covered by bounding spheres (sphere_cover.hpp), checked
// against a Euclidean signed distance field of the map (distance_field.hpp). Implements the
// CollisionChecker contract (collision_checker.hpp), so the front-end runs on it unchanged.
//
// A configuration is in collision when a sphere of link j has ESDF(centre) < radius (an obstacle
// within the sphere: conservative up to the ESDF's voxel rounding), a sphere of link j >= 1 reaches
// below the ground, a sphere centre lies outside the map horizontally, two spheres of a link pair
// that the model does not allow to touch overlap, a joint is outside its limits (+- 1e-6 rad), a
// value is NaN, or no map is set (link 0). Motions and trajectories are sampled so that no sphere
// centre moves more than motion_step_m between samples (bounds in the source).
//
// Thread-safety: const members may be called concurrently once the map is set.

#include <string>

#include "porter/backend/chain_kinematics.hpp"
#include "porter/baselines/distance_field.hpp"
#include "porter/baselines/sphere_cover.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"

namespace porter::baselines {

struct SphereCheckerSettings {
  SphereCoverSettings cover;
  /// ESDF values are clamped to this, m (only distances below the spheres' radius matter here).
  double max_distance_m = 0.5;
  bool check_self_collision = true;
  /// Largest displacement of a sphere centre between samples of a motion, m; <= 0: one voxel.
  double motion_step_m = 0.0;
};

class SphereCollisionChecker final : public planner::CollisionChecker {
 public:
  explicit SphereCollisionChecker(const RobotModel& model, const SphereCheckerSettings& settings = {});

  void set_map(const OccupancyGrid& occupancy_W) override;
  planner::CollisionResult check(const RobotConfiguration& config) const override;
  planner::CollisionResult check_base(const BasePose& base) const override;
  planner::CollisionResult check_motion(const RobotConfiguration& from, const RobotConfiguration& to) const override;
  planner::CollisionResult check_trajectory(const Trajectory& trajectory) const override;
  /// The self-collision and joint-limit part of check_trajectory() (same samples); free of every
  /// self-collision when check_self_collision is off.
  planner::CollisionResult check_trajectory_self(const Trajectory& trajectory) const override;
  /// The cover's inflation, cell_m sqrt(3), plus half a voxel diagonal of the map's ESDF.
  double inflation_bound_m(int link) const override;
  std::string name() const override { return "spheres"; }

  const RobotSpheres& spheres() const { return spheres_; }
  const DistanceField& field() const { return field_; }

 private:
  /// Links 0..up_to_link; with environment = false, joint limits and self-collision only.
  planner::CollisionResult check_links(const RobotConfiguration& config, int up_to_link, bool environment = true) const;
  planner::CollisionResult check_samples(const Trajectory& trajectory, bool environment) const;
  double step_m() const;

  const RobotModel* model_;
  SphereCheckerSettings settings_;
  backend::ChainKinematics kinematics_;
  RobotSpheres spheres_;
  DistanceField field_;
  Eigen::AlignedBox2d map_xy_;
  double resolution_m_ = 0.05;
  double reach_m_ = 0.0;  ///< bound on any sphere centre's distance from the base origin
};

}  // namespace porter::baselines
