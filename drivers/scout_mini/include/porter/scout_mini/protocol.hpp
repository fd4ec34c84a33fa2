#pragma once
// The Agilex Scout Mini CAN protocol, version 2 (500 kbit/s, standard IDs, big-endian fields):
// encoders and decoders shared by the driver (porter-base) and the firmware model.
//
// Sources: Agilex's Scout user manual v1.3.0 (protocol V2, in agilexrobotics/ugv_sdk
// docs/protocol_v2; written for the Scout 2.0, the Mini uses the same V2 parser in ugv_sdk),
// ugv_sdk src/protocol_v2/agilex_protocol_v2.h and agilex_msg_parser_v2.c.
//
//   ID     dir  period  layout
//   0x111  cmd  20 ms   motion: int16 linear mm/s, int16 angular 0.001 rad/s, int16 lateral mm/s,
//                       int16 steering 0.001 rad; the base stops when none arrives for 500 ms
//   0x421  cmd  -       control mode: B0 0 standby, 1 CAN command, 2 serial. The base powers up
//                       in standby and then ignores every other command
//   0x441  cmd  -       error clear: B0 0 all, 1..4 motor n
//   0x211  fb   100 ms  system state: B0 vehicle state, B1 control mode, B2-3 uint16 battery
//                       0.1 V, B4-5 error word, B7 count
//   0x221  fb   20 ms   motion state: int16 linear 0.001 m/s, int16 angular 0.001 rad/s
//   0x251..0x254 20 ms  actuator n high speed: int16 motor rpm, int16 current 0.1 A, int32 pulses
//   0x261..0x264 20 ms  actuator n low speed: uint16 driver voltage 0.1 V, int16 driver
//                       temperature °C, int8 motor temperature °C, uint8 driver status bits
//   0x311  fb   20 ms   odometry: int32 left wheel mm, int32 right wheel mm (cumulative)
//   0x361  fb   ?       BMS: B0 SOC %, B1 SOH %, int16 voltage, current, temperature
//
// Unverified (marked where used): the 0x211 error word's byte layout (the manual puts an 8-bit
// fault byte at B4 with bit0 battery fault, bit1 battery warning, bit2 RC lost and B5 reserved;
// ugv_sdk reads B4-B5 as a big-endian word with masks 0x0001.., i.e. those bits in B5; we follow
// ugv_sdk); the 0x261 status bit names (manual: bit4 "CAN offline"; ugv_sdk: bit4 sensor fault,
// bit5 driver fault, bit6 enabled, bit7 reset; we follow ugv_sdk); the 0x361 scalings and
// period (ugv_sdk parses voltage and current as 0.1 V / 0.1 A); the 0x421 DLC (manual 1, ugv_sdk
// sends 8: we send 8 and accept >= 1).
//
// Encoding: physical values are scaled, rounded to the nearest integer (ties away from zero;
// ugv_sdk truncates toward zero, which biases every command toward zero by up to one unit) and
// saturated to the field's range; NaN encodes as 0.
// Decoding never trusts a frame: a wrong ID, a remote or extended frame, or a DLC shorter than
// the layout is a DecodeStatus, never a read past the data.
//
// Thread-safety: every function is reentrant.

#include <cstdint>
#include <string>

#include "porter/can/can_frame.hpp"

namespace porter::scout_mini {

using can::CanFrame;

namespace id {
inline constexpr std::uint32_t kMotionCommand = 0x111;
inline constexpr std::uint32_t kSystemState = 0x211;
inline constexpr std::uint32_t kMotionState = 0x221;
inline constexpr std::uint32_t kRcState = 0x241;
inline constexpr std::uint32_t kActuatorHighSpeed1 = 0x251;  ///< .. 0x254 (motors 1..4)
inline constexpr std::uint32_t kActuatorLowSpeed1 = 0x261;   ///< .. 0x264
inline constexpr std::uint32_t kOdometry = 0x311;
inline constexpr std::uint32_t kBmsBasic = 0x361;
inline constexpr std::uint32_t kControlMode = 0x421;
inline constexpr std::uint32_t kErrorClear = 0x441;
/// Protocol V1 IDs (older bases): 0x130 motion command, 0x151 a feedback frame only V1 sends.
inline constexpr std::uint32_t kV1MotionCommand = 0x130;
inline constexpr std::uint32_t kV1Feedback = 0x151;
}  // namespace id

inline constexpr int kNumMotors = 4;

enum class ControlMode : std::uint8_t { standby = 0, can = 1, serial = 2, remote = 3 };
enum class VehicleState : std::uint8_t { normal = 0, estop = 1, exception = 2 };

/// Names for logs; "unknown(7)" for values outside the enum.
std::string to_string(ControlMode mode);
std::string to_string(VehicleState state);

enum class DecodeStatus { ok, wrong_id, remote_frame, extended_id, too_short };
const char* to_string(DecodeStatus status);

// ---- 0x211 error word (ugv_sdk masks; see the header comment) ------------------------------------
namespace error_bit {
inline constexpr std::uint16_t kBatteryUnderVoltageFault = 0x0001;
inline constexpr std::uint16_t kBatteryUnderVoltageWarning = 0x0002;
inline constexpr std::uint16_t kRcSignalLost = 0x0004;
inline constexpr std::uint16_t kMotor1Comm = 0x0008;  ///< motor n: 0x0008 << (n - 1)
inline constexpr std::uint16_t kMotor2Comm = 0x0010;
inline constexpr std::uint16_t kMotor3Comm = 0x0020;
inline constexpr std::uint16_t kMotor4Comm = 0x0040;
inline constexpr std::uint16_t kSteerEncoder = 0x0080;
inline constexpr std::uint16_t kMotorDriver = 0x0100;
inline constexpr std::uint16_t kHighLevelComm = 0x0200;
/// Bits that are faults (the base stops); the rest are warnings.
inline constexpr std::uint16_t kFaults = 0x0001 | 0x0008 | 0x0010 | 0x0020 | 0x0040 | 0x0080 |
                                         0x0100 | 0x0200;
}  // namespace error_bit

/// "battery_under_voltage_fault, motor2_comm" for the set bits (unnamed bits as "bit11");
/// "" for 0.
std::string error_names(std::uint16_t bits);

// ---- 0x261 driver status bits (ugv_sdk names) -----------------------------------------------------
namespace driver_bit {
inline constexpr std::uint8_t kInputVoltageLow = 0x01;
inline constexpr std::uint8_t kMotorOverheat = 0x02;
inline constexpr std::uint8_t kDriverOverload = 0x04;
inline constexpr std::uint8_t kDriverOverheat = 0x08;
inline constexpr std::uint8_t kSensorFault = 0x10;
inline constexpr std::uint8_t kDriverFault = 0x20;
inline constexpr std::uint8_t kDriverEnabled = 0x40;
inline constexpr std::uint8_t kDriverReset = 0x80;
}  // namespace driver_bit

/// "motor_overheat, driver_enabled" for the set bits; "" for 0.
std::string driver_status_names(std::uint8_t bits);

// ---- commands -----------------------------------------------------------------------------------
struct MotionCommand {
  double v_mps = 0.0;         ///< forward speed of the base frame B along x_B
  double omega_radps = 0.0;   ///< yaw rate about z_B, counter-clockwise positive
  double lateral_mps = 0.0;   ///< omni version only; 0 on the Scout Mini
  double steering_rad = 0.0;  ///< Ackermann bases only; 0 on the Scout Mini
};
CanFrame encode_motion_command(const MotionCommand& command);
DecodeStatus decode_motion_command(const CanFrame& frame, MotionCommand& out);

CanFrame encode_control_mode(ControlMode mode);
/// `raw_mode` is B0 as sent (may be outside ControlMode).
DecodeStatus decode_control_mode(const CanFrame& frame, std::uint8_t& raw_mode);

/// target 0 = clear every error, 1..4 = clear motor n's error.
CanFrame encode_error_clear(std::uint8_t target);
DecodeStatus decode_error_clear(const CanFrame& frame, std::uint8_t& target);

// ---- feedback -----------------------------------------------------------------------------------
struct SystemState {
  std::uint8_t vehicle_state = 0;  ///< VehicleState value as sent
  std::uint8_t control_mode = 0;   ///< ControlMode value as sent
  double battery_voltage_v = 0.0;
  std::uint16_t error_bits = 0;    ///< error_bit::* (layout unverified, see above)
  std::uint8_t count = 0;          ///< rolling counter, +1 per frame
};
CanFrame encode_system_state(const SystemState& state);
DecodeStatus decode_system_state(const CanFrame& frame, SystemState& out);

struct MotionState {
  double v_mps = 0.0;
  double omega_radps = 0.0;
  double lateral_mps = 0.0;
  double steering_rad = 0.0;
};
CanFrame encode_motion_state(const MotionState& state);
DecodeStatus decode_motion_state(const CanFrame& frame, MotionState& out);

struct ActuatorHighSpeed {
  int motor = 0;                ///< 0..3 for IDs 0x251..0x254
  double speed_rpm = 0.0;       ///< integer rpm on the wire
  double current_a = 0.0;
  std::int32_t pulse_count = 0;
};
/// motor outside 0..3 is clamped into range.
CanFrame encode_actuator_high_speed(const ActuatorHighSpeed& state);
DecodeStatus decode_actuator_high_speed(const CanFrame& frame, ActuatorHighSpeed& out);

struct ActuatorLowSpeed {
  int motor = 0;                      ///< 0..3 for IDs 0x261..0x264
  double driver_voltage_v = 0.0;
  double driver_temperature_c = 0.0;  ///< integer °C on the wire
  double motor_temperature_c = 0.0;   ///< integer °C, int8
  std::uint8_t driver_status = 0;     ///< driver_bit::*
};
CanFrame encode_actuator_low_speed(const ActuatorLowSpeed& state);
DecodeStatus decode_actuator_low_speed(const CanFrame& frame, ActuatorLowSpeed& out);

struct Odometry {
  std::int32_t left_mm = 0;   ///< cumulative left wheel travel (wraps as int32)
  std::int32_t right_mm = 0;
};
CanFrame encode_odometry(const Odometry& odometry);
DecodeStatus decode_odometry(const CanFrame& frame, Odometry& out);

struct BmsBasic {
  double soc_pct = 0.0;          ///< 0..100 (uint8)
  double soh_pct = 0.0;
  double voltage_v = 0.0;        ///< 0.1 V units (unverified)
  double current_a = 0.0;        ///< 0.1 A units (unverified)
  double temperature_c = 0.0;    ///< 0.1 °C units (unverified)
};
CanFrame encode_bms_basic(const BmsBasic& bms);
DecodeStatus decode_bms_basic(const CanFrame& frame, BmsBasic& out);

/// What a frame says about the protocol version the base speaks: 0x151 is sent only by V1
/// bases, 0x221 and 0x241 only by V2 bases (ugv_sdk's protocol detector).
enum class ProtocolHint { none, v1, v2 };
ProtocolHint protocol_hint(const CanFrame& frame);

/// Nearest integer of value * scale, saturated to [lo, hi]; NaN -> 0.
std::int32_t scale_round(double value, double scale, std::int32_t lo, std::int32_t hi);

}  // namespace porter::scout_mini
