#include "sim_devices.hpp"

#include <algorithm>

#include "porter/scout_mini/firmware.hpp"
#include "sim_piper.hpp"

namespace porter::sim {

HostedDevice make_device(const std::string& kind, const SimConfig& config,
                         const RobotModel& robot, const Scene& scene) {
  HostedDevice device;
  if (kind == "scout_mini") {
    scout_mini::FirmwareParams params = config.scout_mini;
    params.track_width_m = robot.base.track_width_m;
    params.wheel_radius_m = robot.base.wheel_radius_m;
    const scout_mini::PlanarPose start{scene.start.base.x_m, scene.start.base.y_m,
                                       scene.start.base.yaw_rad};
    auto firmware = std::make_unique<scout_mini::ScoutMiniFirmware>(params, start);
    const scout_mini::ScoutMiniFirmware* fw = firmware.get();
    device.base_source = std::make_unique<FunctionBaseSource>([fw] {
      BaseTruth truth;
      truth.pose_W = {fw->pose().x_m, fw->pose().y_m, fw->pose().yaw_rad};
      truth.v_mps = fw->v_mps();
      truth.omega_radps = fw->omega_radps();
      return truth;
    });
    device.node = std::move(firmware);
  } else if (kind == "piper") {
    piper::PiperFirmwareParams params;
    const JointVector lower = robot.lower_limits();
    const JointVector upper = robot.upper_limits();
    const JointVector q0 = config.arm_joints_rad ? *config.arm_joints_rad : scene.start.q_rad;
    for (int j = 0; j < piper::kNumJoints; ++j) {
      params.lower_rad[j] = lower[j];
      params.upper_rad[j] = upper[j];
      params.max_speed_radps[j] = config.piper.max_speed_radps;
      params.max_accel_radps2[j] = config.piper.max_accel_radps2;
      params.initial_q_rad[j] = q0[j];
    }
    params.enable_delay_s = config.piper.enable_delay_s;
    params.gripper_max_m = config.piper.gripper_max_m;
    params.gripper_speed_mps = config.piper.gripper_speed_mps;
    auto arm = std::make_unique<SimulatedPiper>(params);
    const piper::PiperFirmware* fw = &arm->firmware();
    device.joint_source = std::make_unique<FunctionJointSource>([fw] {
      JointTruth truth;
      for (int j = 0; j < piper::kNumJoints; ++j) {
        truth.q_rad[j] = fw->truth().q_rad[j];
        truth.qd_radps[j] = fw->truth().qd_radps[j];
      }
      return truth;
    });
    device.node = std::move(arm);
  }
  return device;
}

}  // namespace porter::sim
