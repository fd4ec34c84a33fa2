#pragma once
// porter-state's adapter between LCM messages and porter::state types: BASE_STATE, LIO_POSE and
// ARM_STATE are validated and converted; ROBOT_STATE is built from a FusedState.
//
// Inputs arrive from the network: a conversion never throws, it returns the value or a reason.
// Thread-safety: reentrant.

#include <optional>
#include <string>

#include "porter/arm_state_t.hpp"
#include "porter/base_state_t.hpp"
#include "porter/pose_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/state/fusion.hpp"

namespace porter::state_app {

inline constexpr const char* kProcessName = "porter-state";

template <class T>
struct Converted {
  std::optional<T> value;
  std::string error;  ///< why the message is unusable ("" on success)
};

/// Checks finiteness of the odometry pose and velocities.
Converted<state::OdometrySample> to_odometry(const base_state_t& msg);
/// Checks frame_id / child_frame_id against the config, a finite position and a non-zero
/// finite quaternion; the heading is the quaternion's rotation about z (yaw of ZYX angles).
Converted<state::LioSample> to_lio(const pose_t& msg, const std::string& frame_id,
                                   const std::string& child_frame_id);
/// Checks num_joints (must be 6), the array lengths and finiteness.
Converted<state::ArmSample> to_arm(const arm_state_t& msg);

/// ROBOT_STATE for a fused state (num_joints 0 until an arm sample was received).
robot_state_t make_robot_state(const state::FusedState& fused, const std::string& frame_id);

}  // namespace porter::state_app
