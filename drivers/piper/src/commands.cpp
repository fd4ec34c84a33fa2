#include "porter/piper/commands.hpp"

#include <algorithm>

namespace porter::piper {

const char* to_string(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::ok: return "ok";
    case DecodeStatus::wrong_id: return "wrong_id";
    case DecodeStatus::short_frame: return "short_frame";
    case DecodeStatus::bad_dlc: return "bad_dlc";
    case DecodeStatus::invalid_value: return "invalid_value";
  }
  return "unknown";
}

using wire::check;

can::CanFrame encode_enable(const EnableCommand& cmd) {
  can::CanFrame f = wire::frame8(id::kMotorEnable);
  f.data[0] = cmd.motor;
  f.data[1] = cmd.enable ? kEnableFlagEnable : kEnableFlagDisable;
  return f;
}

DecodeStatus decode_enable(const can::CanFrame& f, EnableCommand& out) {
  const DecodeStatus s = check(f, id::kMotorEnable, 2);
  if (s != DecodeStatus::ok) return s;
  const std::uint8_t motor = f.data[0];
  const std::uint8_t flag = f.data[1];
  if (!((motor >= 1 && motor <= kMotorAllJoints) || motor == kMotorAll)) return DecodeStatus::invalid_value;
  if (flag != kEnableFlagEnable && flag != kEnableFlagDisable) return DecodeStatus::invalid_value;
  out.motor = motor;
  out.enable = flag == kEnableFlagEnable;
  return DecodeStatus::ok;
}

can::CanFrame encode_mode(const ModeCommand& cmd) {
  can::CanFrame f = wire::frame8(id::kMotionCtrl2);
  f.data[0] = cmd.ctrl_mode;
  f.data[1] = cmd.move_mode;
  f.data[2] = std::min<std::uint8_t>(cmd.speed_pct, 100);
  f.data[3] = cmd.mit_mode;
  f.data[4] = cmd.residence_time_s;
  f.data[5] = cmd.installation;
  return f;
}

DecodeStatus decode_mode(const can::CanFrame& f, ModeCommand& out) {
  const DecodeStatus s = check(f, id::kMotionCtrl2, 6);
  if (s != DecodeStatus::ok) return s;
  if (f.data[2] > 100) return DecodeStatus::invalid_value;
  out.ctrl_mode = f.data[0];
  out.move_mode = f.data[1];
  out.speed_pct = f.data[2];
  out.mit_mode = f.data[3];
  out.residence_time_s = f.data[4];
  out.installation = f.data[5];
  return DecodeStatus::ok;
}

can::CanFrame encode_motion(const MotionCommand& cmd) {
  can::CanFrame f = wire::frame8(id::kMotionCtrl1);
  f.data[0] = cmd.estop;
  f.data[1] = cmd.track_ctrl;
  f.data[2] = cmd.drag_teach;
  return f;
}

DecodeStatus decode_motion(const can::CanFrame& f, MotionCommand& out) {
  const DecodeStatus s = check(f, id::kMotionCtrl1, 3);
  if (s != DecodeStatus::ok) return s;
  if (f.data[0] > estop_action::kResume) return DecodeStatus::invalid_value;
  out.estop = f.data[0];
  out.track_ctrl = f.data[1];
  out.drag_teach = f.data[2];
  return DecodeStatus::ok;
}

can::CanFrame encode_joint_target_pair(const JointPair& pair) {
  const int index = std::clamp(pair.first / 2, 0, 2);
  can::CanFrame f = wire::frame8(id::kJointCtrl12 + static_cast<std::uint32_t>(index));
  wire::put_i32(f, 0, pair.mdeg[0]);
  wire::put_i32(f, 4, pair.mdeg[1]);
  return f;
}

std::array<can::CanFrame, 3> encode_joint_targets(const std::array<double, kNumJoints>& q_rad) {
  std::array<can::CanFrame, 3> frames;
  for (int i = 0; i < 3; ++i) {
    JointPair pair;
    pair.first = 2 * i;
    pair.mdeg = {rad_to_mdeg(q_rad[2 * i]), rad_to_mdeg(q_rad[2 * i + 1])};
    frames[i] = encode_joint_target_pair(pair);
  }
  return frames;
}

DecodeStatus decode_joint_target_pair(const can::CanFrame& f, JointPair& out) {
  if (f.id < id::kJointCtrl12 || f.id > id::kJointCtrl56) return DecodeStatus::wrong_id;
  const DecodeStatus s = check(f, f.id, 8);
  if (s != DecodeStatus::ok) return s;
  out.first = 2 * static_cast<int>(f.id - id::kJointCtrl12);
  out.mdeg = {wire::get_i32(f, 0), wire::get_i32(f, 4)};
  return DecodeStatus::ok;
}

GripperCommand gripper_command(double stroke_m, double effort_nm, std::uint8_t code) {
  GripperCommand g;
  g.stroke_um = round_saturate_i32(stroke_m * 1e6);
  const std::int32_t effort = round_saturate_i32(effort_nm * 1e3);
  g.effort_mnm = static_cast<std::uint16_t>(std::clamp<std::int32_t>(effort, 0, kGripperEffortMaxMilliNm));
  g.code = code;
  return g;
}

can::CanFrame encode_gripper(const GripperCommand& cmd) {
  can::CanFrame f = wire::frame8(id::kGripperCtrl);
  wire::put_i32(f, 0, cmd.stroke_um);
  wire::put_u16(f, 4, std::min(cmd.effort_mnm, kGripperEffortMaxMilliNm));
  f.data[6] = cmd.code;
  f.data[7] = cmd.set_zero ? kGripperSetZero : 0x00;
  return f;
}

DecodeStatus decode_gripper(const can::CanFrame& f, GripperCommand& out) {
  const DecodeStatus s = check(f, id::kGripperCtrl, 8);
  if (s != DecodeStatus::ok) return s;
  const std::uint16_t effort = wire::get_u16(f, 4);
  if (effort > kGripperEffortMaxMilliNm || f.data[6] > gripper_code::kEnableClearError ||
      (f.data[7] != 0x00 && f.data[7] != kGripperSetZero)) {
    return DecodeStatus::invalid_value;
  }
  out.stroke_um = wire::get_i32(f, 0);
  out.effort_mnm = effort;
  out.code = f.data[6];
  out.set_zero = f.data[7] == kGripperSetZero;
  return DecodeStatus::ok;
}

}  // namespace porter::piper
