#pragma once
// Piper feedback frames (arm -> host): decoders for the driver, encoders for the firmware model.
// Layouts (big-endian, 8 data bytes):
//
//   0x2A1 status     B0 ctrl_mode  B1 arm_status  B2 move-mode feedback  B3 teach state
//                    B4 motion status (0 target reached, 1 moving)  B5 trajectory point
//                    B6-7 uint16 err_code: B6 bits 0-5 joint 1-6 angle limit,
//                    B7 bits 0-5 joint 1-6 communication error (faults.hpp names them)
//   0x2A2..0x2A4     flange pose, int32 pairs (X,Y) (Z,RX) (RY,RZ): 0.001 mm and 0.001 degree,
//                    RX,RY,RZ = roll, pitch, yaw with R = Rz(RZ)·Ry(RY)·Rx(RX)
//   0x2A5..0x2A7     joint angles, int32 pairs (J1,J2) (J3,J4) (J5,J6), 0.001 degree
//   0x2A8 gripper    B0-3 int32 stroke 0.001 mm  B4-5 int16 effort 0.001 N·m  B6 status bits
//                    (bit 6 enabled, bit 7 zeroed; bits 0-5 faults, see faults.hpp)
//   0x251..0x256     motor i high-speed: B0-1 int16 speed 0.001 rad/s, B2-3 int16 current
//                    0.001 A, B4-7 int32 position (unit unverified: the SDK docstring says "rad";
//                    Porter reads joint angles from 0x2A5..0x2A7 and never uses this field)
//   0x261..0x266     motor i low-speed: B0-1 uint16 bus voltage 0.1 V, B2-3 int16 driver
//                    temperature °C, B4 int8 motor temperature °C, B5 status bits (bit 6
//                    enabled; others faults.hpp), B6-7 uint16 bus current 0.001 A
//
// Rates (inferred, see the hardware reference: 3040 frames/s for one arm): 0x2A1..0x2A8 and
// 0x251..0x256 at 200 Hz, 0x261..0x266 at 40 Hz.
//
// Thread-safety: pure functions. Failure: decoders return a DecodeStatus and leave `out`
// unspecified unless ok; they never read at or past the dlc.

#include <array>
#include <cstdint>

#include "porter/can/can_frame.hpp"
#include "porter/piper/protocol.hpp"

namespace porter::piper {

// ---- 0x2A1 status ---------------------------------------------------------------------------------
namespace arm_status {
inline constexpr std::uint8_t kNormal = 0x00;
inline constexpr std::uint8_t kEmergencyStop = 0x01;
inline constexpr std::uint8_t kNoSolution = 0x02;
inline constexpr std::uint8_t kSingularity = 0x03;
inline constexpr std::uint8_t kTargetExceedsLimit = 0x04;
inline constexpr std::uint8_t kJointCommError = 0x05;
inline constexpr std::uint8_t kBrakeNotReleased = 0x06;
inline constexpr std::uint8_t kCollision = 0x07;
inline constexpr std::uint8_t kTeachOverspeed = 0x08;
inline constexpr std::uint8_t kJointAbnormal = 0x09;
inline constexpr std::uint8_t kOtherError = 0x0A;
inline constexpr std::uint8_t kTeachRecord = 0x0B;
inline constexpr std::uint8_t kTeachExecute = 0x0C;
inline constexpr std::uint8_t kTeachPause = 0x0D;
inline constexpr std::uint8_t kControllerOverTemperature = 0x0E;
inline constexpr std::uint8_t kResistorOverTemperature = 0x0F;
}  // namespace arm_status

struct StatusFeedback {
  std::uint8_t ctrl_mode = 0;
  std::uint8_t arm_status = 0;
  std::uint8_t move_mode = 0;
  std::uint8_t teach_state = 0;
  std::uint8_t motion_status = 0;   ///< 0 target reached, 1 not yet
  std::uint8_t trajectory_point = 0;
  std::uint16_t err_code = 0;       ///< high byte = B6 (angle limits), low byte = B7 (comm errors)
};
/// err_code bits: angle limit of joint j (0-based) is bit 8 + j, communication error bit j.
inline constexpr std::uint16_t err_angle_limit_bit(int joint) { return static_cast<std::uint16_t>(1u << (8 + joint)); }
inline constexpr std::uint16_t err_comm_bit(int joint) { return static_cast<std::uint16_t>(1u << joint); }

can::CanFrame encode_status(const StatusFeedback& s);
DecodeStatus decode_status(const can::CanFrame& frame, StatusFeedback& out);

// ---- 0x2A2..0x2A4 flange pose ---------------------------------------------------------------------
/// One end-pose frame: `index` 0 = (X, Y), 1 = (Z, RX), 2 = (RY, RZ); X,Y,Z in 0.001 mm,
/// RX,RY,RZ in 0.001 degree.
struct EndPosePair {
  int index = 0;
  std::array<std::int32_t, 2> value{};
};
can::CanFrame encode_end_pose_pair(const EndPosePair& p);
DecodeStatus decode_end_pose_pair(const can::CanFrame& frame, EndPosePair& out);

// ---- 0x2A5..0x2A7 joint angles --------------------------------------------------------------------
/// One joint-angle frame: joints `first` and `first + 1` (0-based: 0, 2 or 4), 0.001 degree.
struct JointAnglePair {
  int first = 0;
  std::array<std::int32_t, 2> mdeg{};
};
can::CanFrame encode_joint_angle_pair(const JointAnglePair& p);
DecodeStatus decode_joint_angle_pair(const can::CanFrame& frame, JointAnglePair& out);

// ---- 0x2A8 gripper --------------------------------------------------------------------------------
inline constexpr std::uint8_t kGripperStatusEnabled = 0x40;
inline constexpr std::uint8_t kGripperStatusZeroed = 0x80;

struct GripperFeedback {
  std::int32_t stroke_um = 0;   ///< 0.001 mm
  std::int16_t effort_mnm = 0;  ///< 0.001 N·m
  std::uint8_t status = 0;
  double stroke_m() const { return static_cast<double>(stroke_um) * 1e-6; }
  double effort_nm() const { return static_cast<double>(effort_mnm) * 1e-3; }
  bool enabled() const { return (status & kGripperStatusEnabled) != 0; }
};
can::CanFrame encode_gripper_feedback(const GripperFeedback& g);
/// Needs 7 bytes (B7 is unused).
DecodeStatus decode_gripper_feedback(const can::CanFrame& frame, GripperFeedback& out);

// ---- 0x251..0x256 high-speed motor feedback -------------------------------------------------------
struct HighSpeedFeedback {
  int joint = 0;                  ///< 0-based (0x251 -> 0)
  std::int16_t speed_mradps = 0;  ///< 0.001 rad/s (joint velocity)
  std::int16_t current_ma = 0;    ///< 0.001 A
  std::int32_t position_raw = 0;  ///< unit unverified (see above)
  double speed_radps() const { return static_cast<double>(speed_mradps) * 1e-3; }
  double current_a() const { return static_cast<double>(current_ma) * 1e-3; }
};
/// Torque constants from the SDK (arm_feedback_high_spd.py): N·m per A of motor current,
/// joints 1-3 and 4-6. Firmware up to V1.8-2 reports joints 1-3 a factor 4 low (SDK Q&A §3.2);
/// not corrected here.
inline constexpr std::array<double, kNumJoints> kTorqueConstantNmPerA = {1.18125, 1.18125, 1.18125,
                                                                          0.95844, 0.95844, 0.95844};
can::CanFrame encode_high_speed(const HighSpeedFeedback& h);
/// Accepts 0x251..0x256.
DecodeStatus decode_high_speed(const can::CanFrame& frame, HighSpeedFeedback& out);

// ---- 0x261..0x266 low-speed motor feedback --------------------------------------------------------
inline constexpr std::uint8_t kDriverStatusEnabled = 0x40;

struct LowSpeedFeedback {
  int joint = 0;                     ///< 0-based (0x261 -> 0)
  std::uint16_t voltage_dv = 0;      ///< 0.1 V
  std::int16_t driver_temp_c = 0;    ///< °C
  std::int8_t motor_temp_c = 0;      ///< °C
  std::uint8_t status = 0;           ///< bit 6 enabled; faults.hpp names the others
  std::uint16_t bus_current_ma = 0;  ///< 0.001 A
  bool enabled() const { return (status & kDriverStatusEnabled) != 0; }
};
can::CanFrame encode_low_speed(const LowSpeedFeedback& l);
/// Accepts 0x261..0x266.
DecodeStatus decode_low_speed(const can::CanFrame& frame, LowSpeedFeedback& out);

}  // namespace porter::piper
