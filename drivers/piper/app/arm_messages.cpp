#include "arm_messages.hpp"

#include <cmath>

#include "porter/piper/faults.hpp"

namespace porter::piper {

std::optional<ArmCommand> to_command(const porter::arm_cmd_t& msg, std::string& why) {
  if (msg.num_joints != kNumJoints) {
    why = "num_joints is " + std::to_string(msg.num_joints) + ", the arm has " + std::to_string(kNumJoints);
    return std::nullopt;
  }
  if (msg.q_rad.size() != static_cast<std::size_t>(kNumJoints)) {
    why = "q_rad has " + std::to_string(msg.q_rad.size()) + " values";
    return std::nullopt;
  }
  ArmCommand cmd;
  cmd.enabled = msg.enabled;
  for (int j = 0; j < kNumJoints; ++j) {
    cmd.q_rad[j] = msg.q_rad[j];
    if (!std::isfinite(cmd.q_rad[j])) {
      why = "q_rad[" + std::to_string(j) + "] is not finite";
      return std::nullopt;
    }
  }
  cmd.speed_pct = std::isfinite(msg.speed_pct) ? msg.speed_pct : 0.0;
  cmd.has_gripper = msg.has_gripper;
  if (msg.has_gripper) {
    if (!std::isfinite(msg.gripper_m) || !std::isfinite(msg.gripper_effort_nm)) {
      why = "gripper_m or gripper_effort_nm is not finite";
      return std::nullopt;
    }
    cmd.gripper_m = msg.gripper_m;
    cmd.gripper_effort_nm = msg.gripper_effort_nm;
  }
  return cmd;
}

std::int64_t arm_state_utime(const ArmFeedback& fb, std::int64_t wall_now_us, double mono_now_s) {
  if (fb.joints_t_s < 0.0) return 0;
  if (fb.joints_frame_utime != 0) return fb.joints_frame_utime;
  return wall_now_us - static_cast<std::int64_t>((mono_now_s - fb.joints_t_s) * 1e6);
}

porter::arm_state_t to_arm_state(const ArmFeedback& fb, const ArmDriverStatus& status, std::int64_t utime) {
  porter::arm_state_t m;
  m.utime = utime;
  m.num_joints = kNumJoints;
  m.q_rad.assign(fb.q_rad.begin(), fb.q_rad.end());
  m.qd_radps.assign(fb.qd_radps.begin(), fb.qd_radps.end());
  m.effort_nm.assign(fb.effort_nm.begin(), fb.effort_nm.end());
  m.motor_temperature_c.assign(fb.motor_temperature_c.begin(), fb.motor_temperature_c.end());
  m.joint_status_bits.assign(fb.driver_status.begin(), fb.driver_status.end());
  m.joint_enabled.assign(fb.joint_enabled.begin(), fb.joint_enabled.end());
  m.gripper_m = fb.gripper_m;
  m.gripper_effort_nm = fb.gripper_effort_nm;
  m.ctrl_mode = fb.have_status ? static_cast<std::int8_t>(fb.ctrl_mode) : porter::arm_state_t::CTRL_UNKNOWN;
  m.arm_status = static_cast<std::int8_t>(fb.arm_status);
  m.err_code = fb.err_code;
  m.enabled = status.enabled;
  m.fault = status.fault;
  m.faults = join_names(status.faults);
  m.cmd_stale = status.cmd_stale;
  m.estop_active = status.estop_active;
  m.link_ok = status.link_ok;
  return m;
}

}  // namespace porter::piper
