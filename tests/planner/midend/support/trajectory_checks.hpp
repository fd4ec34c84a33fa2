#pragma once
// Independent checks of a mid-end trajectory, sampled densely through porter::Trajectory (core's
// evaluation, heading rule and wheel rates — not the mid-end's own formulas). Next to the rest
// boundaries core evaluates the rates from its stable expansion around the rest instant
// (trajectory.hpp, kSlowSpeed_mps).

#include <string>
#include <vector>

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
                                     ///< inside a segment (0..2 where a still segment starts or
                                     ///< ends: there the base rests, see rest_junction_error)
  double rest_junction_error = 0.0;  ///< at junctions with a still segment (base held while the
                                     ///< arm moves): |base velocity|, |base acceleration| on both
                                     ///< sides and the base's motion inside still pieces
  int rest_junctions = 0;
  int reversals = 0;                 ///< base direction flips inside a segment (the velocity
                                     ///< turns by more than 90 degrees between 1 ms samples)
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
  double residual_base_worst_t_s = 0.0;  ///< where residual_base_ratio / residual_arm_ratio occur
  double residual_arm_worst_t_s = 0.0;
  double start_heading_error_rad = 0.0;  ///< |yaw(0+) - start node yaw|
  double goal_heading_error_rad = 0.0;
  int samples = 0;
};

/// Pass/fail thresholds: the "Checked" list as the scene tests and
/// scripts/bench-midend apply it.
struct CheckTolerances {
  double boundary = 1e-9;          ///< boundary_error
  double continuity = 1e-7;        ///< continuity_error, gear_error, rest_junction_error
  double gear_yaw_jump_rad = 1e-3;
  double yaw_step_rad = 0.02;      ///< yaw continuous at 1 ms
  double limit_ratio = 1.02;       ///< every limit within 2 %
  double joint_position_excess = 0.02;
  double residual_ratio = 1.02;    ///< residuals within rho (sampled at 1 ms, 2 % slack)
  double heading_rad = 0.05;       ///< start / goal heading
};

/// The properties `r` violates under `tol`, one human-readable line each ("wheel acceleration
/// 1.0734 x limit"); empty when the trajectory passes. A report without a matching reference
/// fails with "pieces do not match the reference path".
std::vector<std::string> violations(const CheckReport& r, const CheckTolerances& tol = {});

/// Samples every dt_s. The reference path is rebuilt from `path` with `settings` so that the
/// pose residuals use the same nearest-in-time node as the mid-end (node times at the same
/// fractions of each piece; the trajectory must have one piece per reference piece, else
/// have_reference is false).
CheckReport check_trajectory(const Trajectory& traj, const planner::WholeBodyPath& path,
                             const MidendLimits& limits, const MidendSettings& settings,
                             double dt_s = 1e-3);

}  // namespace porter::midend::testing
