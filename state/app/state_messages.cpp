#include "state_messages.hpp"

#include <cmath>

namespace porter::state_app {

static_assert(static_cast<int>(state::PoseSource::none) == robot_state_t::POSE_NONE &&
                  static_cast<int>(state::PoseSource::lio) == robot_state_t::POSE_LIO &&
                  static_cast<int>(state::PoseSource::wheel_odom) == robot_state_t::POSE_WHEEL_ODOM,
              "PoseSource values are robot_state_t's POSE_* constants");

Converted<state::OdometrySample> to_odometry(const base_state_t& msg) {
  Converted<state::OdometrySample> out;
  if (!std::isfinite(msg.odom_x_m) || !std::isfinite(msg.odom_y_m) ||
      !std::isfinite(msg.odom_yaw_rad) || !std::isfinite(msg.v_mps) ||
      !std::isfinite(msg.omega_radps)) {
    out.error = "BASE_STATE odometry or velocity is not finite";
    return out;
  }
  state::OdometrySample s;
  s.utime = msg.utime;
  s.T_odom_B = {msg.odom_x_m, msg.odom_y_m, msg.odom_yaw_rad};
  s.v_mps = msg.v_mps;
  s.omega_radps = msg.omega_radps;
  s.estop_active = msg.estop_active;
  out.value = s;
  return out;
}

Converted<state::LioSample> to_lio(const pose_t& msg, const std::string& frame_id,
                                   const std::string& child_frame_id) {
  Converted<state::LioSample> out;
  if (msg.frame_id != frame_id || msg.child_frame_id != child_frame_id) {
    out.error = "LIO_POSE is the pose of '" + msg.child_frame_id + "' in '" + msg.frame_id +
                "', expected '" + child_frame_id + "' in '" + frame_id + "'";
    return out;
  }
  const double n2 = msg.qw * msg.qw + msg.qx * msg.qx + msg.qy * msg.qy + msg.qz * msg.qz;
  if (!std::isfinite(msg.x_m) || !std::isfinite(msg.y_m) || !std::isfinite(n2) || n2 < 1e-12) {
    out.error = "LIO_POSE position or quaternion is not finite, or the quaternion is zero";
    return out;
  }
  // Heading of x_child projected on the plane (ZYX yaw); the scale of q cancels.
  const double yaw = std::atan2(2.0 * (msg.qw * msg.qz + msg.qx * msg.qy),
                                n2 - 2.0 * (msg.qy * msg.qy + msg.qz * msg.qz));
  state::LioSample s;
  s.utime = msg.utime;
  s.T_W_B = {msg.x_m, msg.y_m, yaw};
  out.value = s;
  return out;
}

Converted<state::ArmSample> to_arm(const arm_state_t& msg) {
  Converted<state::ArmSample> out;
  if (msg.num_joints != kNumArmJoints) {
    out.error = "ARM_STATE has " + std::to_string(msg.num_joints) + " joints, expected " +
                std::to_string(kNumArmJoints);
    return out;
  }
  if (msg.q_rad.size() != static_cast<std::size_t>(kNumArmJoints) ||
      msg.qd_radps.size() != static_cast<std::size_t>(kNumArmJoints)) {
    out.error = "ARM_STATE joint arrays disagree with num_joints";
    return out;
  }
  state::ArmSample s;
  s.utime = msg.utime;
  for (int j = 0; j < kNumArmJoints; ++j) {
    s.q_rad[j] = msg.q_rad[static_cast<std::size_t>(j)];
    s.qd_radps[j] = msg.qd_radps[static_cast<std::size_t>(j)];
  }
  if (!s.q_rad.allFinite() || !s.qd_radps.allFinite()) {
    out.error = "ARM_STATE joint angles or velocities are not finite";
    return out;
  }
  s.estop_active = msg.estop_active;
  out.value = s;
  return out;
}

robot_state_t make_robot_state(const state::FusedState& fused, const std::string& frame_id) {
  robot_state_t msg;
  msg.utime = fused.utime;
  msg.frame_id = frame_id;
  msg.x_m = fused.T_W_B.x_m;
  msg.y_m = fused.T_W_B.y_m;
  msg.yaw_rad = fused.T_W_B.yaw_rad;
  msg.v_mps = fused.v_mps;
  msg.omega_radps = fused.omega_radps;
  msg.num_joints = fused.has_arm ? kNumArmJoints : 0;
  msg.q_rad.assign(fused.q_rad.data(), fused.q_rad.data() + msg.num_joints);
  msg.qd_radps.assign(fused.qd_radps.data(), fused.qd_radps.data() + msg.num_joints);
  msg.pose_source = static_cast<std::int8_t>(fused.pose_source);
  msg.base_valid = fused.base_valid;
  msg.arm_valid = fused.arm_valid;
  msg.pose_valid = fused.pose_valid;
  msg.base_utime = fused.base_utime;
  msg.arm_utime = fused.arm_utime;
  msg.pose_utime = fused.pose_utime;
  msg.estop_active = fused.estop_active;
  return msg;
}

}  // namespace porter::state_app
