#pragma once
// porter-arm's configuration (config/drivers/porter_arm.yaml) as parameter structs. Strict:
// load_porter_arm_params() throws porter::LoadError naming the file and the key for an unknown
// key, a missing key, a wrong type or an out-of-range value, and for a robot config that does
// not load.

#include <string>

#include "porter/piper/arm_driver_types.hpp"

namespace porter::piper {

struct PorterArmParams {
  std::string can_bus;          ///< open_can_bus spec
  std::string lcm_url;          ///< "" = $LCM_DEFAULT_URL
  std::string robot_yaml;       ///< resolved path of the robot config
  double loop_rate_hz = 200.0;
  double bus_reopen_period_s = 1.0;
  ArmDriverParams driver;       ///< joint limits filled from the robot model
};

PorterArmParams load_porter_arm_params(const std::string& path);

}  // namespace porter::piper
