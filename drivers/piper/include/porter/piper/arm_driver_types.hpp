#pragma once
// Parameters, inputs and outputs of the Piper driver logic (arm_driver.hpp). Domain types only:
// no LCM, no YAML (porter-arm converts its config and messages into these).
//
// Angles are the robot model's joint angles (rad); the shipped URDF is generated from the
// Piper's DH table so they equal the SDK's joint angles one for one.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "porter/piper/protocol.hpp"

namespace porter::piper {

using JointArray = std::array<double, kNumJoints>;

struct ArmDriverParams {
  /// Joint limits targets are clamped to, rad (the robot model's; see config/drivers/porter_arm.yaml).
  JointArray lower_rad{};
  JointArray upper_rad{};
  /// A command older than this is stale: the driver holds the measured position. > 0.
  double cmd_timeout_s = 0.2;
  /// The link is down when 0x2A1 or any joint-angle frame is older than this. > 0.
  double link_timeout_s = 0.1;
  /// Motor feedback (0x251.., 0x261..) older than this is reported as a fault. > 0.
  double motor_feedback_timeout_s = 0.25;
  /// Period of repeated enable / mode / e-stop / resume / disable frames while unconfirmed. > 0.
  double retry_period_s = 0.1;
  /// Longest wait for the arm to confirm the disable at shutdown. >= 0.
  double shutdown_timeout_s = 0.5;
  /// Speed (% of the firmware's maximum joint speed) used when a command gives none. 1..100.
  int default_speed_pct = 50;
  /// Gripper opening range (m) and effort limit (N·m) commands are clamped to.
  double gripper_min_m = 0.0;
  double gripper_max_m = 0.07;
  double gripper_effort_max_nm = 5.0;
  /// Motor current -> joint torque, N·m per A.
  JointArray torque_constant_nm_per_a{1.18125, 1.18125, 1.18125, 0.95844, 0.95844, 0.95844};
};

/// One joint-space command (from ARM_CMD), already checked for size and finiteness.
struct ArmCommand {
  bool enabled = true;            ///< false = hold the current position
  JointArray q_rad{};             ///< targets, rad (clamped by the driver)
  double speed_pct = 0.0;         ///< (0, 100]; anything else = the default speed
  bool has_gripper = false;
  double gripper_m = 0.0;
  double gripper_effort_nm = 0.0;
};

/// What the driver is doing.
enum class ArmPhase {
  no_link,        ///< no status / joint feedback within link_timeout_s; sends nothing
  enabling,       ///< sending 0x471 enable until every joint reports enabled
  setting_mode,   ///< sending 0x151 (CAN, MOVE J, speed) until 0x2A1 reports CAN + MOVE J
  active,         ///< streaming joint targets (or holding)
  estop,          ///< ESTOP active: sent 0x150 stop, no targets, until released
  releasing,      ///< ESTOP released: sending 0x150 resume until the arm leaves e-stop
  shutting_down,  ///< sending 0x471 disable until confirmed or the timeout
  off,            ///< shutdown finished
};
const char* to_string(ArmPhase phase);

/// The decoded arm as last reported, plus the driver's own flags (what ARM_STATE carries).
struct ArmFeedback {
  JointArray q_rad{};
  JointArray qd_radps{};
  JointArray effort_nm{};
  JointArray motor_temperature_c{};
  JointArray driver_temperature_c{};
  JointArray bus_voltage_v{};
  std::array<std::uint8_t, kNumJoints> driver_status{};
  std::array<bool, kNumJoints> joint_enabled{};
  double gripper_m = 0.0;
  double gripper_effort_nm = 0.0;
  std::uint8_t gripper_status = 0;
  bool have_status = false;       ///< a 0x2A1 has been received
  std::uint8_t ctrl_mode = 0;
  std::uint8_t arm_status = 0;
  std::uint8_t move_mode = 0;
  std::uint8_t motion_status = 0;
  std::uint16_t err_code = 0;
  double joints_t_s = -1.0;       ///< receive time of the newest joint-angle frame, -1 = none
  /// The newest joint-angle frame's own stamp (CanFrame::utime: the kernel's receive time on
  /// SocketCAN, porter-sim's clock on a simulated bus), 0 = none or not stamped.
  std::int64_t joints_frame_utime = 0;
};

/// The driver's view for ARM_STATE, the heartbeat and logs.
struct ArmDriverStatus {
  ArmPhase phase = ArmPhase::no_link;
  bool link_ok = false;
  bool enabled = false;           ///< every joint reports enabled
  bool cmd_stale = false;         ///< holding because no fresh command
  bool holding = false;           ///< streaming the hold position (stale or enabled = false)
  bool estop_active = false;
  bool fault = false;
  std::vector<std::string> faults;  ///< names (faults.hpp), plus the driver's own
};

/// A state change worth a log line, with its cause.
struct ArmEvent {
  enum class Level { info, warn, error } level = Level::info;
  std::string text;
};

/// Counters for the heartbeat and tests.
struct ArmDriverCounters {
  std::uint64_t frames_received = 0;
  std::uint64_t frames_malformed = 0;   ///< Piper feedback IDs that failed to decode
  std::uint64_t frames_ignored = 0;     ///< IDs the driver does not use
  std::uint64_t commands_accepted = 0;
  std::uint64_t targets_clamped = 0;    ///< cycles where at least one target was clamped
  std::uint64_t frames_sent = 0;
};

}  // namespace porter::piper
