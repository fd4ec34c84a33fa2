#pragma once
// porter-tracker's adapter between LCM messages and porter::tracker types: decoded inputs
// (ROBOT_STATE, TRAJECTORY, ESTOP) are validated and converted; outputs (BASE_CMD, ARM_CMD,
// TRACKER_STATUS) are built from a TrackerOutput.
//
// Inputs arrive from the network: a conversion never throws, it returns the value or a reason.
// Thread-safety: reentrant.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/arm_cmd_t.hpp"
#include "porter/base_cmd_t.hpp"
#include "porter/minco_trajectory_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/tracker/tracker.hpp"
#include "porter/tracker_status_t.hpp"

namespace porter::tracker_app {

inline constexpr const char* kProcessName = "porter-tracker";

struct StateConversion {
  std::optional<tracker::MeasuredState> state;
  std::string error;  ///< why the message is unusable ("" on success)
};

/// Checks frame_id (must equal `frame_id`), array lengths against num_joints and finiteness.
/// A message with num_joints = 0 converts (arm unknown); the tracker judges whether it needs it.
StateConversion to_measured_state(const robot_state_t& msg, const std::string& frame_id);

struct TrajectoryConversion {
  std::optional<tracker::TrajectoryOffer> offer;
  std::string error;  ///< names the field and the reason ("" on success)
};

/// Checks dimension and order first (a clear "dimension N, expected 8"), then porter::from_msg.
TrajectoryConversion to_offer(const minco_trajectory_t& msg);

/// BASE_CMD for one step. utime = publish time.
base_cmd_t make_base_cmd(const tracker::TrackerOutput& out, std::int64_t utime);
/// ARM_CMD for one step. When the arm is not enabled the joint arrays are still filled (with the
/// last reference) so the message always carries num_joints entries.
arm_cmd_t make_arm_cmd(const tracker::TrackerOutput& out, double speed_pct, std::int64_t utime);

/// Loop figures reported in TRACKER_STATUS.
struct LoopFigures {
  double last_period_s = 0.0;
  double max_jitter_s = 0.0;  ///< largest |period - nominal| since start
  std::int64_t overruns = 0;
};

/// TRACKER_STATUS. message = the state's cause, or the last refusal while tracking.
tracker_status_t make_status(const tracker::TrackerOutput& out, const std::string& last_refusal,
                             const LoopFigures& loop, std::int64_t utime);

}  // namespace porter::tracker_app
