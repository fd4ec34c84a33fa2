#pragma once
// Operations on an executed trajectory that a re-planning daemon needs: the part still ahead of
// the robot (to check against a new map) and a trajectory that brings the robot to rest from its
// state at a hand-off time (when the way ahead is blocked and no new plan is available).
//
// Frames and units: W; flat output z = [p_x, p_y, q1..q6] (m, rad), times in s from the
// trajectory's t = 0.
// Thread-safety: reentrant. Failure: nothing throws; inputs are valid trajectories.

#include "porter/core/trajectory.hpp"

namespace porter::planner_daemon {

/// The part of `trajectory` from t0_s (clamped to [0, duration]) to its end, with its t = 0 at
/// t0_s: each remaining piece keeps its duration and direction; the first is cut at t0_s (its
/// polynomial re-expanded about the cut). A cut closer than 1 µs to a piece end starts at the
/// next piece; at the very end the tail is one stationary 1 ms piece at the final state.
/// start_yaw_rad is the heading at t0_s.
Trajectory trajectory_tail(const Trajectory& trajectory, double t0_s);

/// Deceleration bounds of a braking trajectory.
struct BrakingLimits {
  double base_decel_mps2 = 1.0;      ///< mean deceleration of the base along its path, m/s^2 (> 0)
  double joint_decel_radps2 = 1.0;   ///< mean deceleration of each joint, rad/s^2 (> 0)
  double min_duration_s = 0.2;       ///< shortest braking piece, s (> 0)
};

/// One quintic piece from the state of `trajectory` at t_s (position, velocity, acceleration of
/// z: the hand-off is continuous) to rest. Its duration T is the largest of min_duration_s,
/// 2 v/a for the base speed and 2 |q̇_j|/a_j per joint, so the mean deceleration stays within
/// the limits (the peak is 1.5 times the mean for a start without acceleration). It ends where
/// `trajectory` is at t_s + T/2 (on the planned path, at the distance a uniform deceleration
/// covers), or at the start point on axes that are at rest. The direction (eta) is that of the
/// piece at t_s.
Trajectory braking_trajectory(const Trajectory& trajectory, double t_s, const BrakingLimits& limits);

}  // namespace porter::planner_daemon
