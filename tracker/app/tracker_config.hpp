#pragma once
// porter-tracker's config file (config/tracker/porter_tracker.yaml) turned into parameters.
// Strict: every key is required, unknown keys and out-of-range values are LoadErrors naming the
// file and the key. The robot's wheel radius, track, wheel speed/acceleration limits and joint
// velocity limits come from the robot config the file names (config/robots/<name>/robot.yaml).
//
// Thread-safety: reentrant. Failure: throws porter::LoadError.

#include <string>

#include "porter/tracker/tracker.hpp"

namespace porter::tracker_app {

struct TrackerConfig {
  std::string file;                 ///< the config file read
  std::string robot_file;           ///< robot.yaml it names (resolved)
  tracker::TrackerParams params;    ///< base limits and joint velocity limits from the robot
  double rate_hz = 100.0;           ///< control rate, Hz
  double status_rate_hz = 10.0;     ///< TRACKER_STATUS rate, Hz (<= rate_hz)
  bool sched_fifo = true;           ///< try SCHED_FIFO at sched_priority (logged when refused)
  int sched_priority = 80;          ///< 1..99
  double arm_speed_pct = 100.0;     ///< arm_cmd_t.speed_pct, (0, 100]
  double stats_log_period_s = 60.0; ///< period of the loop-statistics log line, s (> 0)
};

/// Reads the tracker config and the robot config it names.
TrackerConfig load_tracker_config(const std::string& path);

}  // namespace porter::tracker_app
