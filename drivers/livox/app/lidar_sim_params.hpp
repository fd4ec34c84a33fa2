#pragma once
// porter-lidar-sim's parameters and their YAML (config/drivers/porter_lidar_sim.yaml; strict:
// every key required, unknown keys and bad values are LoadErrors naming file and key).

#include <string>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/livox_sim/realtime_sender.hpp"
#include "porter/livox_sim/scripted_motion.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"

namespace porter::livox::app {

struct LidarSimSetup {
  sim::Mid360SimParams sensor;
  sim::RealtimeSenderParams network;
  RobotModel robot;                     ///< payload attached when one is configured
  Scene scene;
  std::vector<sim::Waypoint> waypoints; ///< the scene's start configuration when none given
  bool loop = false;
  std::uint16_t command_port = 0;       ///< the sensor's command port; 0 = no command channel
  bool sampling_at_start = true;        ///< stream before any command (a sensor set up earlier)
  double step_period_s = 0.001;
  double duration_s = 0.0;              ///< 0 = until stopped
  std::string robot_file, scene_file, payload_file;
};

/// Loads the tool's config and everything it names (robot, scene, payload).
LidarSimSetup load_lidar_sim_setup(const std::string& path);

}  // namespace porter::livox::app
