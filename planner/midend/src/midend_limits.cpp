#include "porter/midend/midend_limits.hpp"

#include <cmath>

namespace porter::midend {

MidendLimits MidendLimits::from_robot(const RobotModel& robot) {
  MidendLimits l;
  l.wheel_radius_m = robot.base.wheel_radius_m;
  l.track_width_m = robot.base.track_width_m;
  l.wheel_omega_max_radps = robot.base.wheel_omega_max_radps;
  l.wheel_alpha_max_radps2 = robot.base.wheel_alpha_max_radps2;
  l.nonsingular_speed_mps = robot.base.nonsingular_speed_mps;
  for (int j = 0; j < kNumArmJoints; ++j) {
    const ArmJoint& a = robot.joints[static_cast<std::size_t>(j)];
    l.joint_lower_rad[j] = a.lower_rad;
    l.joint_upper_rad[j] = a.upper_rad;
    l.joint_velocity_max_radps[j] = a.velocity_max_radps;
    l.joint_acceleration_max_radps2[j] = a.acceleration_max_radps2;
  }
  return l;
}

bool MidendLimits::valid(std::string* why) const {
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  auto fail = [why](const std::string& s) {
    if (why) *why = s;
    return false;
  };
  if (!positive(wheel_radius_m)) return fail("base.wheel_radius_m must be > 0");
  if (!positive(track_width_m)) return fail("base.track_width_m must be > 0");
  if (!positive(wheel_omega_max_radps)) return fail("base.wheel_omega_max_radps must be > 0");
  if (!positive(wheel_alpha_max_radps2)) return fail("base.wheel_alpha_max_radps2 must be > 0");
  if (!positive(nonsingular_speed_mps)) return fail("base.nonsingular_speed_mps must be > 0");
  if (nonsingular_speed_mps >= max_base_speed_mps()) {
    return fail("base.nonsingular_speed_mps must be below wheel_radius * wheel_omega_max");
  }
  for (int j = 0; j < kNumArmJoints; ++j) {
    const std::string name = "joint " + std::to_string(j + 1);
    if (!std::isfinite(joint_lower_rad[j]) || !std::isfinite(joint_upper_rad[j]) ||
        !(joint_lower_rad[j] < joint_upper_rad[j])) {
      return fail(name + ": need finite lower_rad < upper_rad");
    }
    if (!positive(joint_velocity_max_radps[j])) return fail(name + ": velocity_max_radps must be > 0");
    if (!positive(joint_acceleration_max_radps2[j])) {
      return fail(name + ": acceleration_max_radps2 must be > 0");
    }
  }
  return true;
}

}  // namespace porter::midend
