#pragma once
// Agilex Piper CAN protocol (V2 firmware): identifiers, units and the decode status shared by
// the command and feedback layouts (commands.hpp, feedback.hpp).
//
// Bus facts: 1 Mbit/s, standard 11-bit IDs, every frame 8 data bytes, every multi-byte field
// big-endian (Motorola), signed fields two's complement. Sources: agilexrobotics/piper_sdk
// (can_id.py, protocol_v2/piper_protocol_v2.py), summarised in the project's hardware reference.
//
// Units on the wire: joint angles 0.001 degree, gripper stroke 0.001 mm, torques 0.001 N·m,
// motor speed 0.001 rad/s, currents 0.001 A. One radian is exactly 1000·180/π millidegrees here;
// some published ports use 1000·180/3.14, which is wrong by 0.05 %.
//
// Nothing here allocates, prints or throws. Thread-safety: pure functions and constants.

#include <cmath>
#include <cstdint>
#include <limits>

#include "porter/can/can_frame.hpp"

namespace porter::piper {

inline constexpr int kNumJoints = 6;

/// CAN identifiers (standard 11-bit).
namespace id {
// Commands (host -> arm).
inline constexpr std::uint32_t kMotionCtrl1 = 0x150;   ///< e-stop / resume, trajectory and teach control
inline constexpr std::uint32_t kMotionCtrl2 = 0x151;   ///< control mode, move mode, speed %
inline constexpr std::uint32_t kJointCtrl12 = 0x155;   ///< joint targets J1, J2
inline constexpr std::uint32_t kJointCtrl34 = 0x156;   ///< joint targets J3, J4
inline constexpr std::uint32_t kJointCtrl56 = 0x157;   ///< joint targets J5, J6
inline constexpr std::uint32_t kGripperCtrl = 0x159;   ///< gripper stroke, effort, enable code
inline constexpr std::uint32_t kMotorEnable = 0x471;   ///< enable / disable motors
// Feedback (arm -> host).
inline constexpr std::uint32_t kArmStatus = 0x2A1;     ///< modes, arm status, error word
inline constexpr std::uint32_t kEndPose1 = 0x2A2;      ///< flange X, Y
inline constexpr std::uint32_t kEndPose2 = 0x2A3;      ///< flange Z, RX
inline constexpr std::uint32_t kEndPose3 = 0x2A4;      ///< flange RY, RZ
inline constexpr std::uint32_t kJointFeedback12 = 0x2A5;
inline constexpr std::uint32_t kJointFeedback34 = 0x2A6;
inline constexpr std::uint32_t kJointFeedback56 = 0x2A7;
inline constexpr std::uint32_t kGripperFeedback = 0x2A8;
inline constexpr std::uint32_t kHighSpeed1 = 0x251;    ///< 0x251..0x256: motor 1..6 speed, current, position
inline constexpr std::uint32_t kLowSpeed1 = 0x261;     ///< 0x261..0x266: motor 1..6 voltage, temperatures, status
}  // namespace id

/// Why a frame did not decode. Decoders never read a byte at or past the frame's dlc and never
/// trust the dlc beyond 8.
enum class DecodeStatus {
  ok,
  wrong_id,        ///< the frame is not the layout asked for (other ID, extended ID, or RTR)
  short_frame,     ///< fewer data bytes than the layout needs
  bad_dlc,         ///< dlc > 8 (an invalid frame)
  invalid_value,   ///< a field holds a value the layout does not define (e.g. 0x471 flag 0x05)
};

/// "ok", "wrong_id", "short_frame", "bad_dlc", "invalid_value".
const char* to_string(DecodeStatus status);

/// Millidegrees per radian, exactly 1000·180/π.
inline constexpr double kMilliDegPerRad = 1000.0 * 180.0 / 3.14159265358979323846;

/// Rounds to the nearest integer (halves away from zero) and saturates to int32; NaN gives 0.
inline std::int32_t round_saturate_i32(double v) {
  if (std::isnan(v)) return 0;
  if (v >= 2147483647.0) return std::numeric_limits<std::int32_t>::max();
  if (v <= -2147483648.0) return std::numeric_limits<std::int32_t>::min();
  return static_cast<std::int32_t>(std::lround(v));
}

/// Radians -> 0.001 degree on the wire (rounded to nearest, saturated).
inline std::int32_t rad_to_mdeg(double rad) { return round_saturate_i32(rad * kMilliDegPerRad); }
/// 0.001 degree on the wire -> radians.
inline double mdeg_to_rad(std::int32_t mdeg) { return static_cast<double>(mdeg) / kMilliDegPerRad; }

namespace wire {
// Big-endian field access on a frame's 8-byte payload. Callers check the dlc first.
inline void put_u16(can::CanFrame& f, int at, std::uint16_t v) {
  f.data[at] = static_cast<std::uint8_t>(v >> 8);
  f.data[at + 1] = static_cast<std::uint8_t>(v);
}
inline void put_i16(can::CanFrame& f, int at, std::int16_t v) { put_u16(f, at, static_cast<std::uint16_t>(v)); }
inline void put_u32(can::CanFrame& f, int at, std::uint32_t v) {
  f.data[at] = static_cast<std::uint8_t>(v >> 24);
  f.data[at + 1] = static_cast<std::uint8_t>(v >> 16);
  f.data[at + 2] = static_cast<std::uint8_t>(v >> 8);
  f.data[at + 3] = static_cast<std::uint8_t>(v);
}
inline void put_i32(can::CanFrame& f, int at, std::int32_t v) { put_u32(f, at, static_cast<std::uint32_t>(v)); }
inline std::uint16_t get_u16(const can::CanFrame& f, int at) {
  return static_cast<std::uint16_t>((f.data[at] << 8) | f.data[at + 1]);
}
inline std::int16_t get_i16(const can::CanFrame& f, int at) { return static_cast<std::int16_t>(get_u16(f, at)); }
inline std::uint32_t get_u32(const can::CanFrame& f, int at) {
  return (static_cast<std::uint32_t>(f.data[at]) << 24) | (static_cast<std::uint32_t>(f.data[at + 1]) << 16) |
         (static_cast<std::uint32_t>(f.data[at + 2]) << 8) | static_cast<std::uint32_t>(f.data[at + 3]);
}
inline std::int32_t get_i32(const can::CanFrame& f, int at) { return static_cast<std::int32_t>(get_u32(f, at)); }

/// A standard data frame with `id` and 8 zero bytes (every Piper frame is 8 bytes long).
inline can::CanFrame frame8(std::uint32_t id) {
  can::CanFrame f;
  f.id = id;
  f.dlc = 8;
  return f;
}

/// Common checks before reading `needed` bytes of a frame that must carry `expected_id`.
inline DecodeStatus check(const can::CanFrame& f, std::uint32_t expected_id, int needed) {
  if (f.extended || f.rtr || f.id != expected_id) return DecodeStatus::wrong_id;
  if (f.dlc > 8) return DecodeStatus::bad_dlc;
  if (f.dlc < needed) return DecodeStatus::short_frame;
  return DecodeStatus::ok;
}
}  // namespace wire

}  // namespace porter::piper
