#pragma once
// The simulated devices porter-sim can host, by kind (the `devices` of a bus in its config):
//
//   scout_mini   the Scout Mini firmware model (scout_mini/firmware.hpp); it moves the base, so
//                the world reads the base pose from it
//   piper        the Piper firmware model (piper/piper_firmware.hpp, hosted as SimulatedPiper,
//                sim_piper.hpp); it moves the arm, so the world reads the joint angles from it.
//                Joint limits from the robot model, start angles from arm_joints_rad (or the
//                scene's start), speeds from the config's piper section.
//
// Adding a device: add its kind to known_device_kinds() (sim_config.cpp) and a branch to
// make_device() that builds the node and, when it moves part of the robot, the truth source the
// world reads; link its target to porter_sim_app.
//
// Thread-safety: reentrant.

#include <memory>
#include <string>

#include "porter/can/simulated_node.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/sim/truth_sources.hpp"
#include "sim_config.hpp"

namespace porter::sim {

struct HostedDevice {
  std::unique_ptr<can::SimulatedNode> node;
  std::unique_ptr<BaseSource> base_source;    ///< set when the device moves the base
  std::unique_ptr<JointSource> joint_source;  ///< set when the device moves the arm
};

/// Builds the device of `kind` (one of known_device_kinds()); node is null for an unknown kind.
/// The sources read the node, so they must not outlive it (the Simulator owns both).
HostedDevice make_device(const std::string& kind, const SimConfig& config,
                         const RobotModel& robot, const Scene& scene);

}  // namespace porter::sim
