#include "tracker_messages.hpp"

#include <cmath>

#include "porter/msg/trajectory_msg.hpp"

namespace porter::tracker_app {

static_assert(static_cast<int>(tracker::TrackerState::idle) == tracker_status_t::STATE_IDLE &&
                  static_cast<int>(tracker::TrackerState::tracking) == tracker_status_t::STATE_TRACKING &&
                  static_cast<int>(tracker::TrackerState::finished) == tracker_status_t::STATE_FINISHED &&
                  static_cast<int>(tracker::TrackerState::stale_state) ==
                      tracker_status_t::STATE_STALE_STATE &&
                  static_cast<int>(tracker::TrackerState::stale_trajectory) ==
                      tracker_status_t::STATE_STALE_TRAJECTORY &&
                  static_cast<int>(tracker::TrackerState::estop) == tracker_status_t::STATE_ESTOP &&
                  static_cast<int>(tracker::TrackerState::fault) == tracker_status_t::STATE_FAULT,
              "TrackerState values are tracker_status_t's STATE_* constants");

StateConversion to_measured_state(const robot_state_t& msg, const std::string& frame_id) {
  StateConversion out;
  if (msg.frame_id != frame_id) {
    out.error = "ROBOT_STATE frame '" + msg.frame_id + "', expected '" + frame_id + "'";
    return out;
  }
  if (msg.num_joints < 0 || msg.num_joints > 64 ||
      msg.q_rad.size() != static_cast<std::size_t>(msg.num_joints) ||
      msg.qd_radps.size() != static_cast<std::size_t>(msg.num_joints)) {
    out.error = "ROBOT_STATE joint arrays disagree with num_joints";
    return out;
  }
  if (!std::isfinite(msg.x_m) || !std::isfinite(msg.y_m) || !std::isfinite(msg.yaw_rad) ||
      !std::isfinite(msg.v_mps) || !std::isfinite(msg.omega_radps)) {
    out.error = "ROBOT_STATE base pose or velocity is not finite";
    return out;
  }
  tracker::MeasuredState s;
  s.utime = msg.utime;
  s.pose = {msg.x_m, msg.y_m, msg.yaw_rad};
  s.v_mps = msg.v_mps;
  s.omega_radps = msg.omega_radps;
  s.pose_valid = msg.pose_valid;
  s.base_valid = msg.base_valid;
  s.arm_valid = msg.arm_valid;
  s.num_joints = msg.num_joints;
  s.estop_active = msg.estop_active;
  if (msg.num_joints == kNumArmJoints) {
    for (int j = 0; j < kNumArmJoints; ++j) {
      s.q_rad[j] = msg.q_rad[static_cast<std::size_t>(j)];
      s.qd_radps[j] = msg.qd_radps[static_cast<std::size_t>(j)];
    }
    if (!s.q_rad.allFinite() || !s.qd_radps.allFinite()) {
      out.error = "ROBOT_STATE joint angles or velocities are not finite";
      return out;
    }
  }
  out.state = s;
  return out;
}

TrajectoryConversion to_offer(const minco_trajectory_t& msg) {
  TrajectoryConversion out;
  if (msg.dimension != kTrajDim) {
    out.error = "dimension " + std::to_string(msg.dimension) + ", expected " +
                std::to_string(kTrajDim);
    return out;
  }
  TrajectoryMsgResult converted = from_msg(msg);
  if (!converted.ok()) {
    out.error = converted.error;
    return out;
  }
  StampedTrajectory& st = *converted.value;
  out.offer = tracker::TrajectoryOffer{std::move(st.trajectory), msg.utime, st.start_utime,
                                       st.plan_id, st.frame_id};
  return out;
}

base_cmd_t make_base_cmd(const tracker::TrackerOutput& out, std::int64_t utime) {
  base_cmd_t msg;
  msg.utime = utime;
  msg.enabled = out.base_enabled;
  msg.v_mps = out.base_enabled ? out.base.v_mps : 0.0;
  msg.omega_radps = out.base_enabled ? out.base.omega_radps : 0.0;
  msg.plan_id = out.plan_id;
  msg.source = kProcessName;
  return msg;
}

arm_cmd_t make_arm_cmd(const tracker::TrackerOutput& out, double speed_pct, std::int64_t utime) {
  arm_cmd_t msg;
  msg.utime = utime;
  msg.enabled = out.arm_enabled;
  msg.num_joints = kNumArmJoints;
  msg.q_rad.resize(kNumArmJoints);
  msg.qd_radps.resize(kNumArmJoints);
  for (int j = 0; j < kNumArmJoints; ++j) {
    msg.q_rad[static_cast<std::size_t>(j)] = out.q_rad[j];
    msg.qd_radps[static_cast<std::size_t>(j)] = out.arm_enabled ? out.qd_radps[j] : 0.0;
  }
  msg.speed_pct = speed_pct;
  msg.has_gripper = false;
  msg.gripper_m = 0.0;
  msg.gripper_effort_nm = 0.0;
  msg.plan_id = out.plan_id;
  msg.source = kProcessName;
  return msg;
}

tracker_status_t make_status(const tracker::TrackerOutput& out, const std::string& last_refusal,
                             const LoopFigures& loop, std::int64_t utime) {
  tracker_status_t msg;
  msg.utime = utime;
  msg.plan_id = out.plan_id;
  msg.state = static_cast<std::int8_t>(out.state);
  msg.t_s = out.t_s;
  msg.duration_s = out.duration_s;
  msg.along_track_error_m = out.error_reference_frame.x_m;
  msg.cross_track_error_m = out.error_reference_frame.y_m;
  msg.yaw_error_rad = out.error_reference_frame.yaw_rad;
  msg.num_joints = kNumArmJoints;
  msg.q_error_rad.resize(kNumArmJoints);
  for (int j = 0; j < kNumArmJoints; ++j) {
    msg.q_error_rad[static_cast<std::size_t>(j)] = out.q_error_rad[j];
  }
  msg.loop_period_s = loop.last_period_s;
  msg.max_loop_jitter_s = loop.max_jitter_s;
  msg.loop_overruns = loop.overruns;
  msg.message = out.state == tracker::TrackerState::tracking ? last_refusal : out.message;
  return msg;
}

}  // namespace porter::tracker_app
