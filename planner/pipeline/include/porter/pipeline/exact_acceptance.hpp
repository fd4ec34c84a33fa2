#pragma once
// Acceptance on exact geometry with an explicit clearance margin: a trajectory is accepted when
// every robot shape (links, gripper, payload, as the robot model describes them: primitives or
// meshes) stays at least `margin_m` from every obstacle of a scene and from the ground, and no
// two bodies the model does not allow to touch meet. The distances are FCL's, computed by the
// independent validator (planner/validation: its own kinematics and trajectory evaluation), over
// samples dense enough that no robot point moves more than `max_step_m` between neighbours.
//
// Why: the kernel check (kernel_acceptance.hpp) decides on voxels with a per-link inflation of
// 8-14 cm, so it rejects trajectories whose true clearance is a few centimetres — exactly the
// trajectories a tunnel or a forest needs. The kernel check stays the planner's fast filter in
// the front-end and inside the stages; this test is the final word, and its margin is the user's.
//
// The kernel check is the fast filter here too. A second kernel map of the same robot side, with
// the obstacles dilated by margin_m + filter_step_m / 2, is checked at samples of the trajectory
// where no robot point moves more than filter_step_m between neighbours (a few thousand checks of
// a few hundred ns each). Where it passes, every link keeps at least that distance from every
// occupied voxel box at the sample (the dilated voxels contain every point closer), hence at
// least margin_m from the obstacles inside them anywhere between samples, and no self-collision
// (the kernel self check is conservative). Only the time windows around the samples it flags are
// checked exactly, each as a trajectory of its own (the pieces cut at the window's ends). Without
// a filter (no kernel robot given) the whole trajectory is checked exactly.
//
// clearance_margin_m() reports the margin so that the back-end aims its safety term at it
// (backend/recheck_margins.hpp, Planner::set_acceptance) instead of at the kernel inflation.
//
// The scene is what the robot will meet: in porter-plan the scene file's obstacles; a map-only
// caller can describe occupied voxels as box obstacles (the voxels cover the obstacles, so the
// clearance to them is a lower bound of the clearance to the obstacles).
//
// Thread-safety: check() is reentrant (each call builds its own FCL objects). Never throws from
// check(); the constructor throws std::invalid_argument for a negative or non-finite margin.

#include <string>

#include "porter/core/payload.hpp"
#include "porter/core/robot_model.hpp"
#include <memory>

#include "porter/core/occupancy_grid.hpp"
#include "porter/core/scene.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "porter/planner/trajectory_acceptance.hpp"

namespace porter::pipeline {

struct ExactAcceptanceSettings {
  /// Least exact clearance to every obstacle and the ground, m (>= 0).
  double margin_m = 0.02;
  /// Largest displacement of any robot point between samples, m (> 0). Between two samples a
  /// point can come at most this close to an obstacle it cleared at both; the margin absorbs it
  /// when margin_m >= max_step_m / 2.
  double max_step_m = 0.01;
  /// Largest displacement of any robot point between the kernel filter's samples, m (> 0); the
  /// filter's dilation grows by half of it.
  double filter_step_m = 0.02;
};

/// What the last exact check found (for logs and results): least clearance over the obstacles
/// and the ground, m, and the obstacle and body where it is reached.
struct ExactClearance {
  double min_m = 0.0;
  std::string obstacle;
  std::string body;
  bool self_collision = false;
  int filter_samples = 0;       ///< kernel filter samples (0: no filter)
  int windows = 0;              ///< time windows checked exactly
  double exact_duration_s = 0;  ///< their total duration
};

class ExactClearanceAcceptance final : public planner::TrajectoryAcceptance {
 public:
  /// `robot`: the robot without its payload; `payload`: attached to the last link by its grasp
  /// (pass an empty Payload for none); `scene`: the obstacles. All copied.
  ExactClearanceAcceptance(RobotModel robot, Payload payload, Scene scene, ExactAcceptanceSettings settings = {});
  /// The same with the kernel filter: `kernel_robot` is the planner's robot side (the robot with
  /// its payload, Planner::kernel_checker().robot()), `map_W` the voxel map of the scene at the
  /// kernels' resolution. Throws std::invalid_argument when the map does not fit the kernels.
  ExactClearanceAcceptance(RobotModel robot, Payload payload, Scene scene, ExactAcceptanceSettings settings,
                           std::shared_ptr<const planner::KernelRobot> kernel_robot, const OccupancyGrid& map_W);

  planner::AcceptanceResult check(const Trajectory& trajectory) const override;
  std::string name() const override { return "exact"; }
  double clearance_margin_m() const override { return settings_.margin_m; }

  /// check() plus the clearance it measured.
  planner::AcceptanceResult check(const Trajectory& trajectory, ExactClearance* clearance) const;

  const ExactAcceptanceSettings& settings() const { return settings_; }

 private:
  RobotModel robot_;
  Payload payload_;
  Scene scene_;
  ExactAcceptanceSettings settings_;
  std::unique_ptr<planner::KernelCollisionChecker> filter_;
};

}  // namespace porter::pipeline
