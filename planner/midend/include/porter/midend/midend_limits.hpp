#pragma once
// The robot limits the mid-end enforces, read from the robot model (config/, never constants):
// diff-drive wheel radius and track, wheel angular velocity/acceleration bounds, the
// non-singular speed kept at gear switches, and per-joint position/velocity/acceleration
// limits. Plain data; thread-safe to share.

#include <string>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::midend {

struct MidendLimits {
  double wheel_radius_m = 0.0;
  double track_width_m = 0.0;              ///< d_w
  double wheel_omega_max_radps = 0.0;
  double wheel_alpha_max_radps2 = 0.0;
  double nonsingular_speed_mps = 0.0;      ///< v_ns at gear switches
  JointVector joint_lower_rad = JointVector::Zero();
  JointVector joint_upper_rad = JointVector::Zero();
  JointVector joint_velocity_max_radps = JointVector::Zero();
  JointVector joint_acceleration_max_radps2 = JointVector::Zero();

  /// Copies the limits out of a loaded robot model (no validation; see valid()).
  static MidendLimits from_robot(const RobotModel& robot);

  /// Top linear speed when both wheels run at their bound, m/s.
  double max_base_speed_mps() const { return wheel_radius_m * wheel_omega_max_radps; }
  /// Top yaw rate when the wheels run at their bound in opposite directions, rad/s.
  double max_base_yaw_rate_radps() const {
    return 2.0 * wheel_radius_m * wheel_omega_max_radps / track_width_m;
  }

  /// True when every bound is finite and strictly positive, lower < upper for every joint and
  /// v_ns is below the top speed; otherwise false and *why names the first offending field.
  bool valid(std::string* why) const;
};

}  // namespace porter::midend
