#pragma once
// porter-sim's config file (config/drivers/porter_sim.yaml) -> SimConfig.
//
// Strict: every key is required; unknown keys, wrong types and out-of-range values are errors
// naming the file and the key (porter::LoadError). Paths are relative to the file. Bus names and
// device names must be unique; every device kind must be one porter-sim knows (sim_devices.hpp).
//
// Thread-safety: reentrant.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "porter/core/types.hpp"
#include "porter/scout_mini/firmware.hpp"
#include "porter/sim/pose_sensors.hpp"

namespace porter::sim {

struct BusConfig {
  std::string name;                  ///< e.g. "base"; SIM_COMMAND targets it by this name
  std::string can;                   ///< open_can_bus() spec, e.g. "lcm:CAN_BASE"
  std::vector<std::string> devices;  ///< device kinds hosted on it, e.g. "scout_mini"
};

struct SimConfig {
  std::string source;
  std::string lcm_url;                   ///< "" = $LCM_DEFAULT_URL
  std::string scene_path;                ///< resolved
  std::uint64_t scene_seed = 0;
  std::string robot_path;                ///< resolved
  std::string payload_path;              ///< resolved; "" = no payload
  double step_s = 0.001;
  double history_s = 2.0;
  double truth_rate_hz = 100.0;
  double lio_rate_hz = 10.0;
  LioNoise lio_noise;
  std::optional<JointVector> arm_joints_rad;  ///< empty = the scene's start configuration
  std::vector<BusConfig> buses;
  scout_mini::FirmwareParams scout_mini;      ///< track and wheel radius filled from the robot
  double status_period_s = 10.0;
};

SimConfig load_sim_config(const std::string& path);

/// Device kinds porter-sim can host.
const std::vector<std::string>& known_device_kinds();

}  // namespace porter::sim
