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
#include "porter/livox_sim/realtime_sender.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"
#include "porter/piper/piper_firmware.hpp"
#include "porter/scout_mini/firmware.hpp"
#include "porter/sim/pose_sensors.hpp"

namespace porter::sim {

struct BusConfig {
  std::string name;                  ///< e.g. "base"; SIM_COMMAND targets it by this name
  std::string can;                   ///< open_can_bus() spec, e.g. "lcm:CAN_BASE"
  std::vector<std::string> devices;  ///< device kinds hosted on it, e.g. "scout_mini"
};

/// The Piper firmware model's settings porter-sim takes from its config; the joint limits come
/// from the robot model (the URDF's, which porter-arm clamps to), the start angles from
/// arm_joints_rad.
struct PiperSimConfig {
  double max_speed_radps = 3.0;   ///< every joint at 100 % speed
  double max_accel_radps2 = 10.0; ///< every joint
  double enable_delay_s = 0.02;
  double gripper_max_m = 0.07;
  double gripper_speed_mps = 0.05;
};

/// The simulated MID-360 on the robot (lidar_sensor.hpp): its measurement model and where its
/// packets go.
struct LidarSimConfig {
  bool enabled = false;
  livox::sim::RealtimeSenderParams network;  ///< destination address, host and source ports
  livox::sim::Mid360SimParams sensor;        ///< mount resolved to T_B_S from the URDF
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
  /// The arm's angles at start (the Piper model starts there; with no arm device hosted the arm
  /// is held there); empty = the scene's start configuration.
  std::optional<JointVector> arm_joints_rad;
  std::vector<BusConfig> buses;
  scout_mini::FirmwareParams scout_mini;      ///< track and wheel radius filled from the robot
  PiperSimConfig piper;
  LidarSimConfig lidar;
  double status_period_s = 10.0;
};

SimConfig load_sim_config(const std::string& path);

/// Device kinds porter-sim can host.
const std::vector<std::string>& known_device_kinds();

}  // namespace porter::sim
