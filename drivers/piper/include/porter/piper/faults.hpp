#pragma once
// Names for the Piper's status codes and fault bits, for logs and ARM_STATE.
//
// Names are short snake_case words, stable (tools may match them):
//   arm status (0x2A1 B1)    "emergency_stop", "target_exceeds_limit", "collision", ...
//   err_code (0x2A1 B6-7)    "joint2_angle_limit", "joint5_comm_error"
//   motor status (0x26x B5)  "under_voltage", "motor_over_temperature", "over_current",
//                            "driver_over_temperature", "collision_protection",
//                            "driver_error", "stall_protection" (bit 6 "enabled" is no fault)
//   gripper status (0x2A8)   "voltage_low", "motor_over_temperature", "over_current",
//                            "driver_over_temperature", "sensor_error", "driver_error"
//
// Thread-safety: pure functions. Nothing allocates except the append_* functions.

#include <cstdint>
#include <string>
#include <vector>

namespace porter::piper {

/// "standby", "can", "teach", "ethernet", "wifi", "remote", "linkage_teach", "offline", "unknown".
const char* ctrl_mode_name(std::uint8_t ctrl_mode);
/// "move_p", "move_j", "move_l", "move_c", "move_m", "move_cpv", "unknown".
const char* move_mode_name(std::uint8_t move_mode);
/// "normal", "emergency_stop", "no_solution", ..., "unknown".
const char* arm_status_name(std::uint8_t arm_status);
/// True for arm statuses that are faults (everything but normal and the teach states 0x0B-0x0D).
bool arm_status_is_fault(std::uint8_t arm_status);

/// Bits of the motor low-speed status byte that are faults (all but bit 6, "enabled").
inline constexpr std::uint8_t kDriverFaultMask = 0xBF;
/// Bits of the gripper status byte that are faults (bits 0-5).
inline constexpr std::uint8_t kGripperFaultMask = 0x3F;

/// Appends "jointN_angle_limit" / "jointN_comm_error" for every set bit of err_code (bits
/// outside the defined ones give "err_code_bitK").
void append_err_code_names(std::uint16_t err_code, std::vector<std::string>& out);
/// Appends "<prefix><name>" for every fault bit of a motor status byte.
void append_driver_status_names(std::uint8_t status, const std::string& prefix,
                                std::vector<std::string>& out);
/// Appends "<prefix><name>" for every fault bit of the gripper status byte.
void append_gripper_status_names(std::uint8_t status, const std::string& prefix,
                                 std::vector<std::string>& out);

/// Joins names with ", " ("" for none).
std::string join_names(const std::vector<std::string>& names);

}  // namespace porter::piper
