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

/// The instant ARM_STATE's joint angles refer to, µs: the newest joint-angle frame's own stamp
/// when the bus gives one (as porter-base stamps BASE_STATE), so the angles share the clock of
/// the other devices' stamps (porter-sim's clock in simulation, which falls behind the wall
/// clock when porter-sim runs below real time); else the wall-clock time of its receipt
/// (wall_now_us - (mono_now_s - joints_t_s)); 0 when no joint-angle frame arrived yet.
std::int64_t arm_state_utime(const ArmFeedback& fb, std::int64_t wall_now_us, double mono_now_s);

/// Driver state -> ARM_STATE. `utime` is arm_state_utime().
porter::arm_state_t to_arm_state(const ArmFeedback& fb, const ArmDriverStatus& status, std::int64_t utime);

}  // namespace porter::piper
