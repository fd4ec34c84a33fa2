#pragma once
// porter-sim's conversions between LCM messages and the simulation's types (the one adapter file
// of the process).
//
// Thread-safety: reentrant.

#include <cstdint>

#include "porter/pose_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/sim/pose_sensors.hpp"
#include "porter/sim/sim_command.hpp"
#include "porter/sim/world.hpp"
#include "porter/sim_command_t.hpp"

namespace porter::sim {

/// Checks and converts a SIM_COMMAND message. Refused (ok false, message says why): an unknown
/// command, an empty target, a CAN ID outside 0..0x1FFFFFFF, an error code <= 0, a duration
/// outside [0, 3600] s, non-finite box fields.
SimResult to_sim_command(const porter::sim_command_t& msg, SimCommand& out);

/// SIM_TRUTH: the exact state, pose_source POSE_SIM_TRUTH, everything valid.
porter::robot_state_t to_truth_message(const RobotSample& sample, std::int64_t utime);

/// LIO_POSE: B in W ("world" / "base"), the covariance when the sample has one.
porter::pose_t to_lio_message(const PoseSample& sample, std::int64_t utime);

}  // namespace porter::sim
