#pragma once
// porter-base's conversions between LCM messages and the driver's types (the one adapter file of
// the process).
//
// Thread-safety: reentrant.

#include <cstdint>

#include "porter/base_cmd_t.hpp"
#include "porter/base_state_t.hpp"
#include "porter/scout_mini/base_driver.hpp"

namespace porter::scout_mini {

VelocityCommand to_command(const porter::base_cmd_t& msg);

/// BASE_STATE from the driver's feedback; `utime` stamps it (the newest feedback frame's time,
/// or now when there is none).
porter::base_state_t to_base_state(const BaseFeedback& feedback, std::int64_t utime);

}  // namespace porter::scout_mini
