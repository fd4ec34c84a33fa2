#pragma once
// The decisions a re-planning daemon makes about the trajectory being executed, as functions of
// explicit times (no clocks, no threads):
//   - where the remaining part of the trajectory first meets the current map
//     (first_collision_s);
//   - what to do about it (choose_handoff): nothing, re-plan from the state at a hand-off time
//     ahead on the trajectory (the new trajectory starts exactly there, so the command stays
//     continuous), or brake at once because a re-plan could not take over before the robot
//     needs to stop;
//   - whether a map is fresh enough to plan on (map_age_problem).
//
// Times are seconds on the executed trajectory (t = 0 at its start) unless named *_utime (µs,
// the messages' clock).
// Thread-safety: reentrant; first_collision_s only reads the checker (const members, map set).

#include <cstdint>
#include <optional>
#include <string>

#include "porter/core/trajectory.hpp"
#include "porter/planner/collision/kernel_collision_checker.hpp"
#include "porter/planner_daemon/trajectory_ops.hpp"

namespace porter::planner_daemon {

/// The earliest time in [t_from_s, duration] at which `trajectory` is in collision on the
/// checker's map (environment or self), or nullopt when the rest is free. The remaining pieces
/// are checked whole (KernelCollisionChecker::check_trajectory); inside the first one that
/// collides, configurations are checked every step_s (> 0) from its start, so the answer is
/// never later than the first colliding sample. A colliding piece none of whose samples collides
/// (a graze between samples) reports its start.
std::optional<double> first_collision_s(const planner::KernelCollisionChecker& checker, const Trajectory& trajectory,
                                        double t_from_s, double step_s);

/// The configuration of `trajectory` at t_s (base pose with the trajectory's heading, joints).
RobotConfiguration configuration_at(const Trajectory& trajectory, double t_s);

struct HandoffParams {
  /// Time from a decision to the start of a re-planned trajectory, s: the planner's worst-case
  /// time plus the time to reach the tracker. The hand-off is now + lead_s.
  double lead_s = 2.0;
  /// Time from a decision to the start of a braking trajectory, s (publishing and delivery).
  double latency_s = 0.05;
  BrakingLimits braking;
};

enum class HandoffAction {
  kNone,    ///< the remaining part is free (or nothing is executing)
  kReplan,  ///< re-plan from the state at handoff_s; brake from there if the plan fails
  kBrake,   ///< stop now: a braking trajectory from handoff_s
};
/// "none", "replan", "brake".
const char* to_string(HandoffAction a);

struct HandoffChoice {
  HandoffAction action = HandoffAction::kNone;
  double handoff_s = 0.0;   ///< trajectory time at which the new trajectory takes over
  /// The trajectory time whose position a brake from handoff_s comes to rest at (handoff_s plus
  /// half the brake's duration: braking_trajectory() ends on the path there).
  double stop_s = 0.0;
  std::string reason;       ///< for the status and the log
};

/// What to do at trajectory time now_s about a collision at collision_s (nullopt: none) on a
/// trajectory of `duration_s`:
///   - none when there is no collision ahead;
///   - kReplan at handoff = now + lead when a brake that starts there (should the re-plan fail)
///     comes to rest before collision_s (stop_s < collision_s); a handoff past the end is moved
///     to the end (the robot is at rest there, the re-plan starts from rest);
///   - kBrake at now + latency otherwise: waiting for a new plan would let the robot reach the
///     obstacle. Its stop_s may lie past collision_s (the obstacle was seen too late to stop
///     before it; braking at once still shortens the way into it).
/// The brake's length comes from braking_trajectory() at the respective time.
HandoffChoice choose_handoff(const Trajectory& trajectory, double now_s, std::optional<double> collision_s,
                             const HandoffParams& params);

/// "" when a map stamped map_utime may be planned on at now_utime; otherwise why not ("map is
/// 3.20 s old, limit 2.00 s"). A map stamped in the future by more than the limit is refused too
/// (clocks disagree).
std::string map_age_problem(std::int64_t map_utime, std::int64_t now_utime, double max_age_s);

}  // namespace porter::planner_daemon
