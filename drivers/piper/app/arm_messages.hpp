#pragma once
// porter-arm's conversions between LCM messages and the driver's domain types (the one adapter
// file of the process).

#include <cstdint>
#include <optional>
#include <string>

#include "porter/arm_cmd_t.hpp"
#include "porter/arm_state_t.hpp"
#include "porter/piper/arm_driver_types.hpp"

namespace porter::piper {

/// ARM_CMD -> ArmCommand; nullopt with `why` set when the message is unusable (joint count not
/// 6, array sizes that disagree with num_joints, non-finite values).
std::optional<ArmCommand> to_command(const porter::arm_cmd_t& msg, std::string& why);

/// Driver state -> ARM_STATE. `utime` is the wall-clock receive time of the newest joint-angle
/// frame (0 when none arrived yet).
porter::arm_state_t to_arm_state(const ArmFeedback& fb, const ArmDriverStatus& status, std::int64_t utime);

}  // namespace porter::piper
