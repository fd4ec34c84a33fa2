#pragma once
// What a plan is asked to do: from which state, to which goal, how far through the pipeline, with
// which seed, and the caller's cancellation flag. Plain data.
//
// Frames and units: W (world), base pose of B's origin and heading of x_B; flat output
// z = [p_x, p_y, q1..q6] (m, rad) and its time derivatives (m/s, rad/s, m/s^2, rad/s^2).

#include <cstdint>
#include <optional>

#include "porter/core/trajectory.hpp"
#include "porter/core/types.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::pipeline {

/// The last stage a plan runs.
enum class Stages {
  kFront,  ///< the front-end path only
  kMid,    ///< + the MINCO mid-end and its acceptance test (a self-colliding first solve is retried)
  kFull,   ///< + the back-end when the mid-end's trajectory is not accepted
};
/// "front", "mid", "full".
const char* to_string(Stages s);

/// The state a plan starts from: a configuration and the flat output's velocity and acceleration
/// there. At rest (both zero) for a robot standing still; for a hand-off onto a new trajectory
/// while moving, the state of the executed trajectory at the hand-off time (on_trajectory()).
/// A moving base must move along its heading (forward or in reverse: the diff-drive constraint),
/// and the front-end's first driving direction must match it (PlanResult says kInvalidStart
/// otherwise: the front-end does not yet choose its first direction from the start state).
struct StartState {
  RobotConfiguration config;
  TrajVector velocity = TrajVector::Zero();      ///< d/dt [p_x, p_y, q] in W: m/s, rad/s
  TrajVector acceleration = TrajVector::Zero();  ///< m/s^2, rad/s^2

  static StartState at_rest(const RobotConfiguration& config) {
    StartState s;
    s.config = config;
    return s;
  }
  /// The state of `trajectory` at t_s (clamped to [0, duration]): position, heading, velocity
  /// and acceleration of the flat output.
  static StartState on_trajectory(const Trajectory& trajectory, double t_s);
  bool at_rest() const { return velocity.isZero(0.0) && acceleration.isZero(0.0); }
};

/// The goal: a base pose with tolerances and an arm configuration that is fixed or free.
struct GoalSpec {
  BasePose base;  ///< pose of B in W
  /// How far the plan's final base pose may be from `base` (m, rad; negative: the settings'
  /// defaults). The exact pose is planned when it is valid; otherwise the nearest valid pose
  /// within the tolerance (PlanResult::goal says which).
  double position_tolerance_m = -1.0;
  double yaw_tolerance_rad = -1.0;
  /// The arm at the goal (rad); nullopt: free, the planner chooses a valid configuration, the
  /// start's arm when it fits.
  std::optional<JointVector> arm_q_rad;

  static GoalSpec exact(const RobotConfiguration& goal) {
    GoalSpec g;
    g.base = goal.base;
    g.position_tolerance_m = 0.0;
    g.yaw_tolerance_rad = 0.0;
    g.arm_q_rad = goal.q_rad;
    return g;
  }
};

struct PlanRequest {
  StartState start;
  GoalSpec goal;
  /// Seed of every random choice of the plan: same map, request and seed, same result (while no
  /// stage stops on its budget).
  std::uint64_t seed = 0;
  Stages stages = Stages::kFull;
  /// Set by another thread to end the plan early (PlanResult::status kCanceled). Optional; must
  /// outlive plan().
  const planner::CancelFlag* cancel = nullptr;
  /// How long the caller can wait for this plan, from the call, s; 0: the settings' budgets alone.
  /// The back-end is the stage that runs to its budget when it has not converged; when the stages
  /// before it leave more of this time than its budget, it takes that instead (a daemon
  /// re-planning for a hand-off two seconds away need not give up after 0.3 s).
  double time_available_s = 0.0;
};

}  // namespace porter::pipeline
