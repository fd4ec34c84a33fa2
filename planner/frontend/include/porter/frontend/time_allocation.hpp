#pragma once
// Initial time allocation for front-end paths (the mid-end's initial guess for the MINCO piece
// durations).
//
// Base: each step between consecutive samples is an arc (length from the chord and the yaw
// change, curvature kappa = dyaw / length). Its speed is capped by the wheel-speed limit,
// v <= f_v * omega_max * r_w / (1 + |kappa| d_w / 2), and its acceleration likewise by the
// wheel acceleration limit; the speed is zero at both path ends and at every change of driving
// direction. A forward/backward pass gives the fastest trapezoidal profile under these caps.
// Arm: a step lasts at least max_j |dq_j| / (f_q * qdot_max_j). A step lasts the larger of the
// two, and at least min_step_time_s.
//
// Units: s, m, rad. Thread-safety: pure functions.

#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/frontend/reeds_shepp.hpp"
#include "porter/frontend/whole_body_rrt.hpp"

namespace porter::frontend {

struct TimeAllocationSettings {
  /// Fraction of the wheel-speed limit the base plans with (0 .. 1].
  double base_speed_fraction = 0.6;
  /// Fraction of the wheel-acceleration limit the base plans with (0 .. 1].
  double base_accel_fraction = 0.5;
  /// Fraction of each joint's velocity limit the arm plans with (0 .. 1].
  double joint_speed_fraction = 0.8;
  /// Shortest step, s (> 0).
  double min_step_time_s = 0.02;
};

bool validate_settings(const TimeAllocationSettings& s, std::string* why);

/// Durations of the N-1 base steps between N base samples (eta as in BaseSample).
std::vector<double> base_step_times(const RobotModel& model, const std::vector<BaseSample>& samples,
                                    const TimeAllocationSettings& settings);

/// Durations of the N-1 whole-body steps (base profile and arm speed limits).
std::vector<double> whole_body_step_times(const RobotModel& model, const std::vector<WholeBodySample>& samples,
                                          const TimeAllocationSettings& settings);

/// Arc length (m) and unsigned curvature (1/m) of the constant-curvature arc from a to b whose
/// chord is a -> b (the yaw change is split evenly).
void step_arc(const BasePose& a, const BasePose& b, double* length_m, double* curvature_1pm);

}  // namespace porter::frontend
