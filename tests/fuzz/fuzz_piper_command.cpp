// Fuzz target: every Piper command decoder (what the firmware model reads) on arbitrary frames;
// a frame that decodes must encode back to itself (for the bytes the layout defines).
#include <cstdint>

#include "piper_fuzz_input.hpp"
#include "porter/piper/commands.hpp"

using namespace porter::piper;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  for (std::size_t at = 0; at + fuzz::kRecordSize <= size; at += fuzz::kRecordSize) {
    const porter::can::CanFrame f = fuzz::record_at(data + at).frame;
    EnableCommand e;
    if (decode_enable(f, e) == DecodeStatus::ok) {
      const porter::can::CanFrame back = encode_enable(e);
      if (back.data[0] != f.data[0] || back.data[1] != f.data[1]) __builtin_trap();
    }
    ModeCommand m;
    if (decode_mode(f, m) == DecodeStatus::ok) {
      const porter::can::CanFrame back = encode_mode(m);
      for (int i = 0; i < 6; ++i) {
        if (back.data[i] != f.data[i]) __builtin_trap();
      }
    }
    MotionCommand mo;
    if (decode_motion(f, mo) == DecodeStatus::ok && mo.estop > estop_action::kResume) __builtin_trap();
    JointPair p;
    if (decode_joint_target_pair(f, p) == DecodeStatus::ok && encode_joint_target_pair(p) != f) __builtin_trap();
    GripperCommand g;
    if (decode_gripper(f, g) == DecodeStatus::ok && encode_gripper(g) != f) __builtin_trap();
  }
  return 0;
}
