#pragma once
// porter-base's config file (config/drivers/porter_base.yaml) -> BaseNodeConfig.
//
// Strict: every key is required, unknown keys and out-of-range values are errors naming the file
// and the key (porter::LoadError). The speed limits must agree with the robot config the file
// names (`robot`): |v| within the wheel-speed limit (wheel_omega_max_radps x wheel_radius_m),
// |omega| within the Scout Mini firmware's 2.5235 rad/s; the track width and wheel radius for
// odometry and the per-wheel limit are the robot config's.
//
// Thread-safety: reentrant.

#include <string>

#include "porter/scout_mini/base_driver.hpp"

namespace porter::scout_mini {

struct BaseNodeConfig {
  std::string source;           ///< the file it was loaded from
  std::string can_bus;          ///< open_can_bus() spec, e.g. "lcm:CAN_BASE", "socketcan:can0"
  std::string lcm_url;          ///< "" = $LCM_DEFAULT_URL
  std::string robot_config;     ///< resolved path of the robot.yaml used
  DriverParams driver;
  double stats_period_s = 30.0; ///< period of the timing line in the log
  int realtime_priority = 0;    ///< SCHED_FIFO priority of the command loop, 0 = normal
};

BaseNodeConfig load_base_config(const std::string& path);

}  // namespace porter::scout_mini
