#pragma once
// Conversion between porter::Trajectory (porter/core/trajectory.hpp) and the LCM message
// porter::minco_trajectory_t published by porter-planner on TRAJECTORY.
//
// Message layout (lcmtypes/minco_trajectory_t.lcm): dimension = kTrajDim (8), order =
// kTrajDegree (5), durations_s[i] / eta[i] per piece, and coeffs[((i * dimension) + d) *
// (order + 1) + k] = coefficient of tau^k of z_d in piece i (tau local to the piece, s).
//
// Thread-safety: reentrant. Failure: from_msg never throws; a message that cannot be a trajectory
// (it arrives from the network) yields a result whose error names the field and the reason.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/core/trajectory.hpp"
#include "porter/minco_trajectory_t.hpp"

namespace porter {

/// A trajectory with the message's metadata.
struct StampedTrajectory {
  Trajectory trajectory;
  int64_t utime = 0;        ///< publish time, us
  int64_t start_utime = 0;  ///< absolute time of the trajectory's t = 0, us (clock of utime)
  int64_t plan_id = 0;      ///< increments per published plan
  std::string frame_id;     ///< frame of p_x, p_y (normally "world")
  std::string payload_id;   ///< payload carried, "" when none
};

struct TrajectoryMsgResult {
  std::optional<StampedTrajectory> value;
  std::string error;  ///< empty on success
  bool ok() const { return value.has_value(); }
};

/// The message for a trajectory. msg.utime is set to start_utime; a publisher that stamps with
/// its own clock overwrites it.
minco_trajectory_t to_msg(const Trajectory& trajectory, int64_t start_utime, int64_t plan_id,
                          const std::string& frame_id, const std::string& payload_id);

/// Validates and converts a message. Fails when dimension != 8 or order != 5, num_pieces < 1,
/// an array's length disagrees with its count (num_pieces, num_coeffs), num_coeffs !=
/// num_pieces * dimension * (order + 1), a duration is not finite and > 0, an eta is not +1/-1,
/// a coefficient or start_yaw_rad is not finite, or Trajectory::create() refuses the pieces (the
/// limits kTrajMin/MaxPieceDuration_s, kTrajMaxTotalDuration_s, kTrajMaxReach in trajectory.hpp).
TrajectoryMsgResult from_msg(const minco_trajectory_t& msg);

}  // namespace porter
