#include "sim_devices.hpp"

#include "porter/scout_mini/firmware.hpp"

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
  }
  return device;
}

}  // namespace porter::sim
