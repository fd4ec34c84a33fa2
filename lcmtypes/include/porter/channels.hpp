#pragma once
// The channel registry: every LCM channel of Porter, declared exactly once (DESIGN §2).
//
// Each channel has a typed descriptor (`kRobotState` is a Channel<porter::robot_state_t>) that
// porter::LcmBus (lcm_bus.hpp) uses for typed publish/subscribe, and an untyped row in
// `kAll` for tools, logs and tests. No other file may spell a channel name as a string
// literal; tests/lcmtypes enforces this.
//
// Fields of a channel:
//   name         LCM channel name. Only [A-Z0-9_], because LCM treats a subscription channel as
//                a regular expression; these names match only themselves. At most 63 chars.
//   type_name    the lcm type carried, without the package (package is always `porter`);
//                equals T::getTypeName() of the typed descriptor (tested).
//   rate_hz      nominal publish rate in Hz; 0 = event-driven (on change / on demand).
//   owner        the process(es) that publish it ("operator" = a user tool such as the planner
//                CLI or scripts/demo; "all" = every Porter process).
//   description  one line for humans (lcm-spy users, README).
//
// Thread-safety: everything here is constexpr data; safe from any thread.

#include <array>
#include <cstddef>
#include <string_view>

#include "porter/arm_cmd_t.hpp"
#include "porter/arm_state_t.hpp"
#include "porter/base_cmd_t.hpp"
#include "porter/base_state_t.hpp"
#include "porter/can_frame_t.hpp"
#include "porter/estop_t.hpp"
#include "porter/imu_t.hpp"
#include "porter/minco_trajectory_t.hpp"
#include "porter/octomap_t.hpp"
#include "porter/payload_t.hpp"
#include "porter/plan_goal_t.hpp"
#include "porter/planner_status_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/pose_t.hpp"
#include "porter/process_heartbeat_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/sim_command_t.hpp"
#include "porter/tracker_status_t.hpp"

namespace porter::channels {

/// One row of the registry, without the C++ message type.
struct ChannelInfo {
  std::string_view name;
  std::string_view type_name;
  double rate_hz = 0.0;
  std::string_view owner;
  std::string_view description;
};

/// A channel that carries messages of lcm type T. Pass it to LcmBus::publish / subscribe.
template <class T>
struct Channel {
  using Message = T;

  constexpr Channel(std::string_view name, std::string_view type_name, double rate_hz,
                    std::string_view owner, std::string_view description)
      : info{name, type_name, rate_hz, owner, description} {}

  constexpr std::string_view name() const { return info.name; }

  ChannelInfo info;
};

// ---- sensing ------------------------------------------------------------------------------------
inline constexpr Channel<porter::point_cloud_t> kLidarPoints{
    "LIDAR_POINTS", "point_cloud_t", 10.0, "porter-lidar",
    "MID-360 scan in the LiDAR frame, per-point time offsets, not motion compensated"};
inline constexpr Channel<porter::imu_t> kLidarImu{
    "LIDAR_IMU", "imu_t", 200.0, "porter-lidar",
    "MID-360 built-in IMU: gyro rad/s, specific force m/s^2"};
inline constexpr Channel<porter::pose_t> kLioPose{
    "LIO_POSE", "pose_t", 10.0, "porter-sim",
    "pose of the base in the world from LiDAR-inertial odometry (FAST-LIO2 bridge on the "
    "robot, porter-sim in simulation)"};

// ---- mapping and planning -----------------------------------------------------------------------
inline constexpr Channel<porter::octomap_t> kMapOctomap{
    "MAP_OCTOMAP", "octomap_t", 2.0, "porter-mapper",
    "occupancy map as an OctoMap binary stream, 2-5 Hz"};
inline constexpr Channel<porter::plan_goal_t> kPlanGoal{
    "PLAN_GOAL", "plan_goal_t", 0.0, "operator",
    "planning request: goal base pose, optional arm configuration, payload id"};
inline constexpr Channel<porter::payload_t> kPayload{
    "PAYLOAD", "payload_t", 0.0, "operator",
    "payload grasped by the gripper: mesh and T_EE_P"};
inline constexpr Channel<porter::minco_trajectory_t> kTrajectory{
    "TRAJECTORY", "minco_trajectory_t", 0.0, "porter-planner",
    "whole-body MINCO trajectory over [p_x, p_y, q1..q6], on demand and on replanning"};
inline constexpr Channel<porter::planner_status_t> kPlannerStatus{
    "PLANNER_STATUS", "planner_status_t", 0.0, "porter-planner",
    "planner state, per-stage status/time/iterations, failure reason"};

// ---- state estimation and control ---------------------------------------------------------------
inline constexpr Channel<porter::robot_state_t> kRobotState{
    "ROBOT_STATE", "robot_state_t", 100.0, "porter-state",
    "fused whole-body state: base pose in the world, base velocities, joint angles/velocities"};
inline constexpr Channel<porter::base_cmd_t> kBaseCmd{
    "BASE_CMD", "base_cmd_t", 100.0, "porter-tracker",
    "base velocity command (v, omega); stale after 200 ms"};
inline constexpr Channel<porter::arm_cmd_t> kArmCmd{
    "ARM_CMD", "arm_cmd_t", 100.0, "porter-tracker", "arm joint position command"};
inline constexpr Channel<porter::tracker_status_t> kTrackerStatus{
    "TRACKER_STATUS", "tracker_status_t", 10.0, "porter-tracker",
    "tracker state, tracking errors and loop timing (decimated from the 100 Hz loop)"};

// ---- drivers ------------------------------------------------------------------------------------
inline constexpr Channel<porter::base_state_t> kBaseState{
    "BASE_STATE", "base_state_t", 50.0, "porter-base",
    "Scout Mini feedback: measured v/omega, wheel odometry, battery, faults, control mode"};
inline constexpr Channel<porter::arm_state_t> kArmState{
    "ARM_STATE", "arm_state_t", 200.0, "porter-arm",
    "Piper feedback: joint angles/velocities/efforts, enable and fault flags"};
inline constexpr Channel<porter::can_frame_t> kCanBase{
    "CAN_BASE", "can_frame_t", 0.0, "porter-base, porter-sim",
    "LCM-carried CAN bus of the base (500 kbit/s on hardware); every node reads and writes"};
inline constexpr Channel<porter::can_frame_t> kCanArm{
    "CAN_ARM", "can_frame_t", 0.0, "porter-arm, porter-sim",
    "LCM-carried CAN bus of the arm (1 Mbit/s on hardware); every node reads and writes"};

// ---- supervision --------------------------------------------------------------------------------
inline constexpr Channel<porter::estop_t> kEstop{
    "ESTOP", "estop_t", 0.0, "operator",
    "emergency stop: every actuator process halts while active; repeated ~1 Hz by senders"};
inline constexpr Channel<porter::process_heartbeat_t> kHeartbeat{
    "HEARTBEAT", "process_heartbeat_t", 1.0, "all",
    "liveness and health of every Porter process"};

// ---- simulation ---------------------------------------------------------------------------------
inline constexpr Channel<porter::robot_state_t> kSimTruth{
    "SIM_TRUTH", "robot_state_t", 100.0, "porter-sim",
    "ground truth of the simulated robot: exact base pose and velocities, joint angles and "
    "velocities (pose_source = POSE_SIM_TRUTH); for tests, validation and scoring"};
inline constexpr Channel<porter::sim_command_t> kSimCommand{
    "SIM_COMMAND", "sim_command_t", 0.0, "operator",
    "faults and world changes asked of porter-sim: drop a bus, stop a stream, raise an error, "
    "power-cycle a device, add or remove an obstacle"};

/// Every channel, in the order above.
inline constexpr std::array<ChannelInfo, 20> kAll{{
    kLidarPoints.info, kLidarImu.info, kLioPose.info, kMapOctomap.info, kPlanGoal.info,
    kPayload.info, kTrajectory.info, kPlannerStatus.info, kRobotState.info, kBaseCmd.info,
    kArmCmd.info, kTrackerStatus.info, kBaseState.info, kArmState.info, kCanBase.info,
    kCanArm.info, kEstop.info, kHeartbeat.info, kSimTruth.info, kSimCommand.info,
}};

/// The registry row named `name`, or nullptr when no channel has that name.
constexpr const ChannelInfo* find(std::string_view name) noexcept {
  for (const ChannelInfo& info : kAll) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

}  // namespace porter::channels
