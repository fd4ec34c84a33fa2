#include "porter/piper/feedback.hpp"

#include <algorithm>

namespace porter::piper {

using wire::check;

can::CanFrame encode_status(const StatusFeedback& s) {
  can::CanFrame f = wire::frame8(id::kArmStatus);
  f.data[0] = s.ctrl_mode;
  f.data[1] = s.arm_status;
  f.data[2] = s.move_mode;
  f.data[3] = s.teach_state;
  f.data[4] = s.motion_status;
  f.data[5] = s.trajectory_point;
  wire::put_u16(f, 6, s.err_code);
  return f;
}

DecodeStatus decode_status(const can::CanFrame& f, StatusFeedback& out) {
  const DecodeStatus s = check(f, id::kArmStatus, 8);
  if (s != DecodeStatus::ok) return s;
  out.ctrl_mode = f.data[0];
  out.arm_status = f.data[1];
  out.move_mode = f.data[2];
  out.teach_state = f.data[3];
  out.motion_status = f.data[4];
  out.trajectory_point = f.data[5];
  out.err_code = wire::get_u16(f, 6);
  return DecodeStatus::ok;
}

can::CanFrame encode_end_pose_pair(const EndPosePair& p) {
  can::CanFrame f = wire::frame8(id::kEndPose1 + static_cast<std::uint32_t>(std::clamp(p.index, 0, 2)));
  wire::put_i32(f, 0, p.value[0]);
  wire::put_i32(f, 4, p.value[1]);
  return f;
}

DecodeStatus decode_end_pose_pair(const can::CanFrame& f, EndPosePair& out) {
  if (f.id < id::kEndPose1 || f.id > id::kEndPose3) return DecodeStatus::wrong_id;
  const DecodeStatus s = check(f, f.id, 8);
  if (s != DecodeStatus::ok) return s;
  out.index = static_cast<int>(f.id - id::kEndPose1);
  out.value = {wire::get_i32(f, 0), wire::get_i32(f, 4)};
  return DecodeStatus::ok;
}

can::CanFrame encode_joint_angle_pair(const JointAnglePair& p) {
  const int index = std::clamp(p.first / 2, 0, 2);
  can::CanFrame f = wire::frame8(id::kJointFeedback12 + static_cast<std::uint32_t>(index));
  wire::put_i32(f, 0, p.mdeg[0]);
  wire::put_i32(f, 4, p.mdeg[1]);
  return f;
}

DecodeStatus decode_joint_angle_pair(const can::CanFrame& f, JointAnglePair& out) {
  if (f.id < id::kJointFeedback12 || f.id > id::kJointFeedback56) return DecodeStatus::wrong_id;
  const DecodeStatus s = check(f, f.id, 8);
  if (s != DecodeStatus::ok) return s;
  out.first = 2 * static_cast<int>(f.id - id::kJointFeedback12);
  out.mdeg = {wire::get_i32(f, 0), wire::get_i32(f, 4)};
  return DecodeStatus::ok;
}

can::CanFrame encode_gripper_feedback(const GripperFeedback& g) {
  can::CanFrame f = wire::frame8(id::kGripperFeedback);
  wire::put_i32(f, 0, g.stroke_um);
  wire::put_i16(f, 4, g.effort_mnm);
  f.data[6] = g.status;
  return f;
}

DecodeStatus decode_gripper_feedback(const can::CanFrame& f, GripperFeedback& out) {
  const DecodeStatus s = check(f, id::kGripperFeedback, 7);
  if (s != DecodeStatus::ok) return s;
  out.stroke_um = wire::get_i32(f, 0);
  out.effort_mnm = wire::get_i16(f, 4);
  out.status = f.data[6];
  return DecodeStatus::ok;
}

can::CanFrame encode_high_speed(const HighSpeedFeedback& h) {
  can::CanFrame f =
      wire::frame8(id::kHighSpeed1 + static_cast<std::uint32_t>(std::clamp(h.joint, 0, kNumJoints - 1)));
  wire::put_i16(f, 0, h.speed_mradps);
  wire::put_i16(f, 2, h.current_ma);
  wire::put_i32(f, 4, h.position_raw);
  return f;
}

DecodeStatus decode_high_speed(const can::CanFrame& f, HighSpeedFeedback& out) {
  if (f.id < id::kHighSpeed1 || f.id >= id::kHighSpeed1 + kNumJoints) return DecodeStatus::wrong_id;
  const DecodeStatus s = check(f, f.id, 8);
  if (s != DecodeStatus::ok) return s;
  out.joint = static_cast<int>(f.id - id::kHighSpeed1);
  out.speed_mradps = wire::get_i16(f, 0);
  out.current_ma = wire::get_i16(f, 2);
  out.position_raw = wire::get_i32(f, 4);
  return DecodeStatus::ok;
}

can::CanFrame encode_low_speed(const LowSpeedFeedback& l) {
  can::CanFrame f =
      wire::frame8(id::kLowSpeed1 + static_cast<std::uint32_t>(std::clamp(l.joint, 0, kNumJoints - 1)));
  wire::put_u16(f, 0, l.voltage_dv);
  wire::put_i16(f, 2, l.driver_temp_c);
  f.data[4] = static_cast<std::uint8_t>(l.motor_temp_c);
  f.data[5] = l.status;
  wire::put_u16(f, 6, l.bus_current_ma);
  return f;
}

DecodeStatus decode_low_speed(const can::CanFrame& f, LowSpeedFeedback& out) {
  if (f.id < id::kLowSpeed1 || f.id >= id::kLowSpeed1 + kNumJoints) return DecodeStatus::wrong_id;
  const DecodeStatus s = check(f, f.id, 8);
  if (s != DecodeStatus::ok) return s;
  out.joint = static_cast<int>(f.id - id::kLowSpeed1);
  out.voltage_dv = wire::get_u16(f, 0);
  out.driver_temp_c = wire::get_i16(f, 2);
  out.motor_temp_c = static_cast<std::int8_t>(f.data[4]);
  out.status = f.data[5];
  out.bus_current_ma = wire::get_u16(f, 6);
  return DecodeStatus::ok;
}

}  // namespace porter::piper
