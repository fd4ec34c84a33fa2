#include "sim_messages.hpp"

#include <cmath>

namespace porter::sim {
namespace {

SimResult refuse(const std::string& why) { return {false, why}; }

}  // namespace

SimResult to_sim_command(const porter::sim_command_t& msg, SimCommand& out) {
  using K = SimCommand::Kind;
  using M = porter::sim_command_t;
  out = SimCommand{};
  switch (msg.command) {
    case M::DROP_BUS: out.kind = K::drop_bus; break;
    case M::RESTORE_BUS: out.kind = K::restore_bus; break;
    case M::STOP_STREAM: out.kind = K::stop_stream; break;
    case M::RESUME_STREAM: out.kind = K::resume_stream; break;
    case M::RAISE_ERROR: out.kind = K::raise_error; break;
    case M::CLEAR_ERRORS: out.kind = K::clear_errors; break;
    case M::POWER_CYCLE: out.kind = K::power_cycle; break;
    case M::ADD_BOX: out.kind = K::add_box; break;
    case M::REMOVE_OBSTACLE: out.kind = K::remove_obstacle; break;
    default: return refuse("unknown command " + std::to_string(msg.command));
  }
  if (msg.target.empty()) return refuse(std::string(to_string(out.kind)) + ": empty target");
  out.target = msg.target;
  if (out.kind == K::stop_stream || out.kind == K::resume_stream) {
    if (msg.can_id < 0 || msg.can_id > 0x1FFFFFFF) {
      return refuse("can_id " + std::to_string(msg.can_id) + " is not a CAN ID");
    }
    out.can_id = static_cast<std::uint32_t>(msg.can_id);
  }
  if (out.kind == K::raise_error) {
    if (msg.error_code <= 0) return refuse("error_code must be > 0");
    out.error_code = static_cast<std::uint32_t>(msg.error_code);
  }
  if (out.kind == K::power_cycle) {
    if (!(msg.duration_s >= 0.0 && msg.duration_s <= 3600.0)) {
      return refuse("duration_s must be in [0, 3600]");
    }
    out.duration_s = msg.duration_s;
  }
  if (out.kind == K::add_box) {
    out.center_W = Eigen::Vector3d(msg.center_x_m, msg.center_y_m, msg.center_z_m);
    out.size_m = Eigen::Vector3d(msg.size_x_m, msg.size_y_m, msg.size_z_m);
    out.yaw_rad = msg.yaw_rad;
    if (!out.center_W.allFinite() || !out.size_m.allFinite() || !std::isfinite(out.yaw_rad)) {
      return refuse("add_box: centre, size and yaw must be finite");
    }
  }
  return {true, ""};
}

porter::robot_state_t to_truth_message(const RobotSample& s, std::int64_t utime) {
  porter::robot_state_t msg;
  msg.utime = utime;
  msg.frame_id = "world";
  msg.x_m = s.config.base.x_m;
  msg.y_m = s.config.base.y_m;
  msg.yaw_rad = s.config.base.yaw_rad;
  msg.v_mps = s.v_mps;
  msg.omega_radps = s.omega_radps;
  msg.num_joints = kNumArmJoints;
  msg.q_rad.assign(s.config.q_rad.data(), s.config.q_rad.data() + kNumArmJoints);
  msg.qd_radps.assign(s.qd_radps.data(), s.qd_radps.data() + kNumArmJoints);
  msg.pose_source = porter::robot_state_t::POSE_SIM_TRUTH;
  msg.base_valid = true;
  msg.arm_valid = true;
  msg.pose_valid = true;
  msg.base_utime = utime;
  msg.arm_utime = utime;
  msg.pose_utime = utime;
  msg.estop_active = false;
  return msg;
}

porter::pose_t to_lio_message(const PoseSample& s, std::int64_t utime) {
  porter::pose_t msg;
  msg.utime = utime;
  msg.frame_id = "world";
  msg.child_frame_id = "base";
  msg.x_m = s.pose_W.x_m;
  msg.y_m = s.pose_W.y_m;
  msg.z_m = 0.0;
  msg.qw = std::cos(0.5 * s.pose_W.yaw_rad);
  msg.qx = 0.0;
  msg.qy = 0.0;
  msg.qz = std::sin(0.5 * s.pose_W.yaw_rad);
  if (s.has_covariance) {
    msg.num_covariance = 36;
    msg.covariance.assign(s.covariance.begin(), s.covariance.end());
  } else {
    msg.num_covariance = 0;
  }
  return msg;
}

}  // namespace porter::sim
