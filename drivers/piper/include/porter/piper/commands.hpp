#pragma once
// Piper command frames (host -> arm): encoders for the driver, decoders for the firmware model
// and for tools that read a bus. Layouts (big-endian, 8 data bytes, unused bytes zero):
//
//   0x471 enable     B0 motor (1..6 one joint, 7 all joints, 0xFF all joints and the gripper)
//                    B1 0x01 disable, 0x02 enable
//   0x151 mode       B0 ctrl_mode  B1 move_mode  B2 speed % 0..100  B3 mit_mode
//                    B4 residence time s  B5 installation pose
//   0x150 motion 1   B0 e-stop (0x00 none, 0x01 stop, 0x02 resume)  B1 track_ctrl  B2 drag-teach
//   0x155..0x157     int32 pairs (J1,J2) (J3,J4) (J5,J6), 0.001 degree
//   0x159 gripper    B0-3 int32 stroke 0.001 mm  B4-5 uint16 effort 0.001 N·m (0..5000)
//                    B6 code (0x00 disable, 0x01 enable, 0x02 disable + clear error,
//                    0x03 enable + clear error)  B7 0xAE = set the current stroke as zero
//
// Unverified on hardware: whether motor 7 in 0x471 includes the gripper (the SDK's docstrings
// disagree; EnablePiper() sends 7 and treats it as "all joints"). Porter enables with 7 and
// disables with 0xFF.
//
// Thread-safety: pure functions. Failure: decoders return a DecodeStatus; encoders clamp out-of-
// range inputs to the field's range (documented per function) and never fail.

#include <array>
#include <cstdint>

#include "porter/can/can_frame.hpp"
#include "porter/piper/protocol.hpp"

namespace porter::piper {

// ---- 0x471 enable / disable -----------------------------------------------------------------------
inline constexpr std::uint8_t kMotorAllJoints = 7;     ///< every arm joint
inline constexpr std::uint8_t kMotorAll = 0xFF;        ///< every joint and the gripper
inline constexpr std::uint8_t kEnableFlagDisable = 0x01;
inline constexpr std::uint8_t kEnableFlagEnable = 0x02;

struct EnableCommand {
  std::uint8_t motor = kMotorAllJoints;  ///< 1..6, kMotorAllJoints or kMotorAll
  bool enable = true;
};
can::CanFrame encode_enable(const EnableCommand& cmd);
/// invalid_value when B1 is neither 0x01 nor 0x02 or B0 is not 1..7 / 0xFF.
DecodeStatus decode_enable(const can::CanFrame& frame, EnableCommand& out);

// ---- 0x151 control mode, move mode, speed ----------------------------------------------------------
namespace ctrl_mode {
inline constexpr std::uint8_t kStandby = 0x00;
inline constexpr std::uint8_t kCan = 0x01;
inline constexpr std::uint8_t kTeach = 0x02;       ///< feedback only
inline constexpr std::uint8_t kEthernet = 0x03;
inline constexpr std::uint8_t kWifi = 0x04;
inline constexpr std::uint8_t kRemote = 0x05;      ///< feedback only
inline constexpr std::uint8_t kLinkageTeach = 0x06;  ///< feedback only
inline constexpr std::uint8_t kOffline = 0x07;
}  // namespace ctrl_mode
namespace move_mode {
inline constexpr std::uint8_t kMoveP = 0x00;
inline constexpr std::uint8_t kMoveJ = 0x01;
inline constexpr std::uint8_t kMoveL = 0x02;
inline constexpr std::uint8_t kMoveC = 0x03;
inline constexpr std::uint8_t kMoveM = 0x04;   ///< MIT (firmware >= V1.5-2)
inline constexpr std::uint8_t kMoveCpv = 0x05; ///< firmware >= V1.8-1
}  // namespace move_mode
inline constexpr std::uint8_t kMitModePositionVelocity = 0x00;

struct ModeCommand {
  std::uint8_t ctrl_mode = ctrl_mode::kCan;
  std::uint8_t move_mode = move_mode::kMoveJ;
  std::uint8_t speed_pct = 50;      ///< 0..100; the encoder clamps larger values to 100
  std::uint8_t mit_mode = kMitModePositionVelocity;
  std::uint8_t residence_time_s = 0;
  std::uint8_t installation = 0;    ///< 0x00 unchanged, 0x01 upright, 0x02 left, 0x03 right side
};
can::CanFrame encode_mode(const ModeCommand& cmd);
/// invalid_value when the speed byte exceeds 100.
DecodeStatus decode_mode(const can::CanFrame& frame, ModeCommand& out);

// ---- 0x150 emergency stop / resume ----------------------------------------------------------------
namespace estop_action {
inline constexpr std::uint8_t kNone = 0x00;
inline constexpr std::uint8_t kStop = 0x01;
inline constexpr std::uint8_t kResume = 0x02;
}  // namespace estop_action

struct MotionCommand {
  std::uint8_t estop = estop_action::kNone;
  std::uint8_t track_ctrl = 0;
  std::uint8_t drag_teach = 0;
};
can::CanFrame encode_motion(const MotionCommand& cmd);
/// invalid_value when B0 is not 0x00, 0x01 or 0x02.
DecodeStatus decode_motion(const can::CanFrame& frame, MotionCommand& out);

// ---- 0x155..0x157 joint targets -------------------------------------------------------------------
/// One joint-target frame: joints `first` and `first + 1` (0-based: 0, 2 or 4), 0.001 degree.
struct JointPair {
  int first = 0;
  std::array<std::int32_t, 2> mdeg{};
};
/// The three target frames (0x155, 0x156, 0x157) for joint angles in radians, each rounded to
/// the nearest 0.001 degree (halves away from zero) and saturated to int32; NaN encodes as 0.
std::array<can::CanFrame, 3> encode_joint_targets(const std::array<double, kNumJoints>& q_rad);
can::CanFrame encode_joint_target_pair(const JointPair& pair);
/// Accepts 0x155, 0x156 and 0x157.
DecodeStatus decode_joint_target_pair(const can::CanFrame& frame, JointPair& out);

// ---- 0x159 gripper --------------------------------------------------------------------------------
namespace gripper_code {
inline constexpr std::uint8_t kDisable = 0x00;
inline constexpr std::uint8_t kEnable = 0x01;
inline constexpr std::uint8_t kDisableClearError = 0x02;
inline constexpr std::uint8_t kEnableClearError = 0x03;
}  // namespace gripper_code
inline constexpr std::uint8_t kGripperSetZero = 0xAE;
inline constexpr std::uint16_t kGripperEffortMaxMilliNm = 5000;

struct GripperCommand {
  std::int32_t stroke_um = 0;        ///< 0.001 mm (= µm)
  std::uint16_t effort_mnm = 0;      ///< 0.001 N·m, 0..5000
  std::uint8_t code = gripper_code::kEnable;
  bool set_zero = false;             ///< B7 = 0xAE
};
/// Stroke in metres (rounded to 0.001 mm) and effort in N·m (rounded to 0.001 N·m, clamped to
/// 0..5 N·m); the stroke is not clamped here (the driver clamps to its configured range).
GripperCommand gripper_command(double stroke_m, double effort_nm, std::uint8_t code);
can::CanFrame encode_gripper(const GripperCommand& cmd);
/// invalid_value when B6 is not 0x00..0x03, B7 is neither 0x00 nor 0xAE, or the effort > 5000.
DecodeStatus decode_gripper(const can::CanFrame& frame, GripperCommand& out);

}  // namespace porter::piper
