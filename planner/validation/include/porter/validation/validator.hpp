#pragma once
// Mesh-level validation of a planned whole-body trajectory with FCL, independent of the
// planner's collision kernels, SDFs, kinematics and trajectory sampling (it shares only the
// scene, robot and payload loaders and their geometry types).
//
// Checks, over samples in time dense enough that no point of the robot moves more than
// settings.max_step_m between consecutive samples (bounded per body by |dc| + r * angle, with c
// and r the body's bounding centre and radius, refined by bisection), and at least every
// settings.max_dt_s:
//   - every robot shape (links 0..7 and the payload) against every obstacle of the scene; the
//     arm, gripper and payload (not the base) against the ground z = 0 (obstacle "ground");
//   - self-collision between the pairs of bodies the robot model does not allow to touch
//     (adjacent links are allowed; the payload counts as link 7);
//   - joint position, speed and acceleration limits, wheel speed and acceleration limits (the
//     wheel rates where the base moves at >= settings.wheel_rates_min_speed_mps);
//   - the start pose kept and the goal reached (trajectory ends against the scene's start/goal).
// Clearance per obstacle is signed: the least distance over the trajectory from any robot
// shape, negative for penetration (then minus the deepest penetration found).
//
// Units: metres, radians, seconds; poses in the world frame W.
// Thread-safety: reentrant (each call builds its own FCL objects).
// Failure: never throws for a trajectory; the report says what is wrong.

#include <string>
#include <vector>

#include "porter/core/payload.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/validation/chain_kinematics.hpp"
#include "porter/validation/flat_trajectory.hpp"

namespace porter::validation {

struct ValidationSettings {
  /// Largest displacement of any robot point between consecutive samples, m (> 0).
  double max_step_m = 0.01;
  /// Largest time between consecutive samples, s (> 0); limits are checked at every sample.
  double max_dt_s = 0.02;
  /// A limit is kept while |value| / limit <= 1 + limit_tolerance (joint positions: the ratio is
  /// the distance from the range's middle over its half-width).
  double limit_tolerance = 0.02;
  /// Wheel rates are checked where |dp/dt| >= this, m/s (the heading rate is a quotient of
  /// vanishing terms at rest).
  double wheel_rates_min_speed_mps = 0.01;
  /// Goal and start: base position error, m; heading and joint errors, rad.
  double pose_tolerance_m = 0.05;
  double pose_tolerance_rad = 0.05;
  /// Exact distances are computed only where a shape's bounding box comes within this of an
  /// obstacle's, m; an obstacle never that close gets the least box gap as its clearance (a
  /// lower bound, flagged not exact). Collisions are found whatever the horizon.
  double clearance_horizon_m = 0.5;
  /// Check the arm, gripper and payload against the ground plane z = 0.
  bool check_ground = true;
};

struct CollisionEvent {
  bool found = false;
  double t_s = 0.0;          ///< first sample in collision
  std::string body;          ///< robot body (link name or payload:<name>)
  std::string shape;         ///< the body's shape
  std::string obstacle;      ///< obstacle name (or "ground")
  double depth_m = 0.0;      ///< penetration depth at that sample
  int samples = 0;           ///< samples with any collision
};

struct SelfCollisionEvent {
  bool found = false;
  double t_s = 0.0;
  std::string body_a, body_b;
  double depth_m = 0.0;      ///< at the first sample
  int samples = 0;
};

struct ObstacleClearance {
  std::string obstacle;
  double min_m = 0.0;        ///< signed, m
  double t_s = 0.0;          ///< where it is reached
  std::string body;          ///< which body reaches it
  bool exact = true;         ///< false: never within the horizon, min_m is the least box gap
};

struct LimitCheck {
  std::string quantity;      ///< joint_position | joint_velocity | joint_acceleration | wheel_speed | wheel_acceleration
  double worst_ratio = 0.0;  ///< largest |value| / limit over the samples
  double t_s = 0.0;
  std::string where;         ///< joint name, or "left wheel" / "right wheel"
  double value = 0.0, limit = 0.0;
  bool kept = true;
};

struct PoseCheck {
  bool ok = true;
  double position_error_m = 0.0;
  double yaw_error_rad = 0.0;
  double joint_error_rad = 0.0;  ///< largest over the joints
};

struct ValidationReport {
  bool valid = false;
  std::vector<std::string> failures;   ///< one short reason per failed check
  int samples = 0;
  double duration_s = 0.0;
  double max_step_m = 0.0;             ///< largest displacement bound between samples achieved
  CollisionEvent collision;
  SelfCollisionEvent self_collision;
  std::vector<ObstacleClearance> clearances;  ///< scene obstacles in order, then "ground"
  std::vector<LimitCheck> limits;
  PoseCheck start, goal;
  double time_ms = 0.0;                ///< wall time of the validation
};

/// model: the robot without payload; payload: attached to link 7 by its grasp.
ValidationReport validate_trajectory(const RobotModel& model, const Payload& payload,
                                     const Scene& scene, const FlatTrajectory& trajectory,
                                     const ValidationSettings& settings = {});

/// Obstacle and ground clearance of recorded whole-body configurations (e.g. the simulator's
/// ground truth of an executed run), exactly as validate_trajectory checks each of its samples:
/// fills samples, duration_s, clearances, collision, failures, valid and time_ms only (no limits,
/// poses or self-collision: recorded states have no derivatives to check). times_s labels each
/// configuration in the report; the shorter of the two vectors is used.
ValidationReport check_configurations(const RobotModel& model, const Payload& payload, const Scene& scene,
                                      const std::vector<double>& times_s,
                                      const std::vector<WholeBodyConfig>& configs,
                                      const ValidationSettings& settings = {});

/// Sample times used by validate_trajectory (exposed for tests): sorted, first 0, last the
/// duration; *max_step_m receives the largest displacement bound between neighbours.
std::vector<double> sample_times(const RobotModel& model, const Payload& payload,
                                 const FlatTrajectory& trajectory, const ValidationSettings& settings,
                                 double* max_step_m);

/// Whole-body configuration on the trajectory at t (own heading rule, see flat_trajectory.hpp).
WholeBodyConfig config_at(const FlatTrajectory& trajectory, double t_s);

}  // namespace porter::validation
