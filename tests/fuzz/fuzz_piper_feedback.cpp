// Fuzz target: every Piper feedback decoder and the fault-name functions on arbitrary frames
// (every decoder sees every frame, whatever its ID). Input: piper_fuzz_input.hpp records.
#include <cstdint>
#include <string>
#include <vector>

#include "piper_fuzz_input.hpp"
#include "porter/piper/faults.hpp"
#include "porter/piper/feedback.hpp"

using namespace porter::piper;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> names;
  for (std::size_t at = 0; at + fuzz::kRecordSize <= size; at += fuzz::kRecordSize) {
    const porter::can::CanFrame f = fuzz::record_at(data + at).frame;
    StatusFeedback s;
    if (decode_status(f, s) == DecodeStatus::ok) {
      names.clear();
      append_err_code_names(s.err_code, names);
      names.push_back(arm_status_name(s.arm_status));
      names.push_back(ctrl_mode_name(s.ctrl_mode));
      names.push_back(move_mode_name(s.move_mode));
      if (encode_status(s) != f && f.dlc == 8) __builtin_trap();  // decode/encode must agree
    }
    EndPosePair e;
    if (decode_end_pose_pair(f, e) == DecodeStatus::ok && (e.index < 0 || e.index > 2)) __builtin_trap();
    JointAnglePair j;
    if (decode_joint_angle_pair(f, j) == DecodeStatus::ok) {
      if (j.first != 0 && j.first != 2 && j.first != 4) __builtin_trap();
      if (encode_joint_angle_pair(j) != f) __builtin_trap();
    }
    GripperFeedback g;
    if (decode_gripper_feedback(f, g) == DecodeStatus::ok) {
      names.clear();
      append_gripper_status_names(g.status, "gripper_", names);
    }
    HighSpeedFeedback h;
    if (decode_high_speed(f, h) == DecodeStatus::ok && (h.joint < 0 || h.joint >= kNumJoints)) __builtin_trap();
    LowSpeedFeedback l;
    if (decode_low_speed(f, l) == DecodeStatus::ok) {
      if (l.joint < 0 || l.joint >= kNumJoints) __builtin_trap();
      names.clear();
      append_driver_status_names(l.status, "joint_", names);
    }
    if (join_names(names).size() > 4096) __builtin_trap();
  }
  return 0;
}
