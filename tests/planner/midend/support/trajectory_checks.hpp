#pragma once
// Independent checks of a mid-end trajectory, sampled densely through porter::Trajectory (core's
// evaluation, heading rule and wheel rates — not the mid-end's own formulas). Next to the rest
// boundaries core evaluates the rates from its stable expansion around the rest instant
// (trajectory.hpp, kSlowSpeed_mps).

#include "porter/core/trajectory.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend::testing {

struct CheckReport {
  bool finite = true;
  bool have_reference = false;       ///< the pieces matched the rebuilt reference path (the
                                     ///< boundary, heading and residual fields are only then set)
  double boundary_error = 0.0;       ///< max |z - node|, |z_dot|, |z_ddot| at start and goal
  double continuity_error = 0.0;     ///< max jump of derivatives 0..4 at same-direction knots
  double gear_error = 0.0;           ///< at gear switches: position / arm rate jumps and
                                     ///< |base velocity - eta v_ns heading|, |base acceleration|
  int gear_switches = 0;
  double max_gear_yaw_jump_rad = 0.0;  ///< |yaw(t_g + 1e-6) - yaw(t_g - 1e-6)|
  double max_yaw_step_rad = 0.0;       ///< max |yaw(t + dt) - yaw(t)| over the samples
  double wheel_velocity_ratio = 0.0;   ///< max |omega_{l,r}| / omega_max
  double wheel_acceleration_ratio = 0.0;
  double joint_velocity_ratio = 0.0;
  double joint_acceleration_ratio = 0.0;
  double joint_position_excess = 0.0;  ///< max violation of [lower, upper] / (upper - lower)
  double residual_base_ratio = 0.0;    ///< max sqrt(e_b + rho_b^2) / rho_b (<= 1 is inside)
  double residual_arm_ratio = 0.0;
  double start_heading_error_rad = 0.0;  ///< |yaw(0+) - start node yaw|
  double goal_heading_error_rad = 0.0;
  int samples = 0;
};

/// Samples every dt_s. The reference path is rebuilt from `path` with `settings` so that the
/// pose residuals use the same nearest-in-time node as the mid-end (node times at the same
/// fractions of each piece; the trajectory must have one piece per reference piece, else
/// have_reference is false).
CheckReport check_trajectory(const Trajectory& traj, const planner::WholeBodyPath& path,
                             const MidendLimits& limits, const MidendSettings& settings,
                             double dt_s = 1e-3);

}  // namespace porter::midend::testing
