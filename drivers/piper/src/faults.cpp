#include "porter/piper/faults.hpp"

#include "porter/piper/commands.hpp"
#include "porter/piper/feedback.hpp"

namespace porter::piper {

const char* ctrl_mode_name(std::uint8_t m) {
  switch (m) {
    case ctrl_mode::kStandby: return "standby";
    case ctrl_mode::kCan: return "can";
    case ctrl_mode::kTeach: return "teach";
    case ctrl_mode::kEthernet: return "ethernet";
    case ctrl_mode::kWifi: return "wifi";
    case ctrl_mode::kRemote: return "remote";
    case ctrl_mode::kLinkageTeach: return "linkage_teach";
    case ctrl_mode::kOffline: return "offline";
  }
  return "unknown";
}

const char* move_mode_name(std::uint8_t m) {
  switch (m) {
    case move_mode::kMoveP: return "move_p";
    case move_mode::kMoveJ: return "move_j";
    case move_mode::kMoveL: return "move_l";
    case move_mode::kMoveC: return "move_c";
    case move_mode::kMoveM: return "move_m";
    case move_mode::kMoveCpv: return "move_cpv";
  }
  return "unknown";
}

const char* arm_status_name(std::uint8_t s) {
  switch (s) {
    case arm_status::kNormal: return "normal";
    case arm_status::kEmergencyStop: return "emergency_stop";
    case arm_status::kNoSolution: return "no_solution";
    case arm_status::kSingularity: return "singularity";
    case arm_status::kTargetExceedsLimit: return "target_exceeds_limit";
    case arm_status::kJointCommError: return "joint_comm_error";
    case arm_status::kBrakeNotReleased: return "brake_not_released";
    case arm_status::kCollision: return "collision";
    case arm_status::kTeachOverspeed: return "teach_overspeed";
    case arm_status::kJointAbnormal: return "joint_abnormal";
    case arm_status::kOtherError: return "other_error";
    case arm_status::kTeachRecord: return "teach_record";
    case arm_status::kTeachExecute: return "teach_execute";
    case arm_status::kTeachPause: return "teach_pause";
    case arm_status::kControllerOverTemperature: return "controller_over_temperature";
    case arm_status::kResistorOverTemperature: return "discharge_resistor_over_temperature";
  }
  return "unknown";
}

bool arm_status_is_fault(std::uint8_t s) {
  return !(s == arm_status::kNormal || s == arm_status::kTeachRecord ||
           s == arm_status::kTeachExecute || s == arm_status::kTeachPause);
}

void append_err_code_names(std::uint16_t err_code, std::vector<std::string>& out) {
  for (int bit = 0; bit < 16; ++bit) {
    if ((err_code & (1u << bit)) == 0) continue;
    if (bit >= 8 && bit < 8 + kNumJoints) {
      out.push_back("joint" + std::to_string(bit - 7) + "_angle_limit");
    } else if (bit < kNumJoints) {
      out.push_back("joint" + std::to_string(bit + 1) + "_comm_error");
    } else {
      out.push_back("err_code_bit" + std::to_string(bit));
    }
  }
}

void append_driver_status_names(std::uint8_t status, const std::string& prefix,
                                std::vector<std::string>& out) {
  static const char* const names[8] = {"under_voltage",           "motor_over_temperature",
                                       "over_current",            "driver_over_temperature",
                                       "collision_protection",    "driver_error",
                                       nullptr /* bit 6 enabled */, "stall_protection"};
  for (int bit = 0; bit < 8; ++bit) {
    if ((status & (1u << bit)) != 0 && names[bit] != nullptr) out.push_back(prefix + names[bit]);
  }
}

void append_gripper_status_names(std::uint8_t status, const std::string& prefix,
                                 std::vector<std::string>& out) {
  static const char* const names[6] = {"voltage_low",  "motor_over_temperature",
                                       "over_current", "driver_over_temperature",
                                       "sensor_error", "driver_error"};
  for (int bit = 0; bit < 6; ++bit) {
    if ((status & (1u << bit)) != 0) out.push_back(prefix + names[bit]);
  }
}

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) {
    if (!s.empty()) s += ", ";
    s += n;
  }
  return s;
}

}  // namespace porter::piper
