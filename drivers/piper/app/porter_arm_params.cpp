#include "porter_arm_params.hpp"

#include "porter/core/robot_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::piper {

PorterArmParams load_porter_arm_params(const std::string& path) {
  const yaml::Reader root = yaml::Reader::load_file(path);
  root.expect_keys({"can_bus", "lcm_url", "robot", "loop_rate_hz", "cmd_timeout_s", "link_timeout_s",
                    "motor_feedback_timeout_s", "retry_period_s", "shutdown_timeout_s",
                    "default_speed_pct", "bus_reopen_period_s", "gripper"});
  PorterArmParams p;
  p.can_bus = root.get("can_bus").as_string();
  if (p.can_bus.find(':') == std::string::npos) {
    root.get("can_bus").fail("expected TRANSPORT:TARGET (socketcan:can0, slcan:DEVICE@BITRATE, "
                             "lcm:CAN_ARM[@URL], memory:NAME), got '" + p.can_bus + "'");
  }
  p.lcm_url = root.get("lcm_url").as_string();
  p.robot_yaml = yaml::resolve_path(path, root.get("robot").as_string());
  p.loop_rate_hz = root.get("loop_rate_hz").as_in(10.0, 1000.0, "Hz");
  ArmDriverParams& d = p.driver;
  d.cmd_timeout_s = root.get("cmd_timeout_s").as_in(0.0, 10.0, "s", true);
  d.link_timeout_s = root.get("link_timeout_s").as_in(0.0, 5.0, "s", true);
  d.motor_feedback_timeout_s = root.get("motor_feedback_timeout_s").as_in(0.0, 5.0, "s", true);
  d.retry_period_s = root.get("retry_period_s").as_in(0.0, 5.0, "s", true);
  d.shutdown_timeout_s = root.get("shutdown_timeout_s").as_in(0.0, 10.0, "s");
  const yaml::Reader speed = root.get("default_speed_pct");
  d.default_speed_pct = speed.as_int();
  if (d.default_speed_pct < 1 || d.default_speed_pct > 100) {
    speed.fail("expected an integer in [1, 100], got " + std::to_string(d.default_speed_pct));
  }
  p.bus_reopen_period_s = root.get("bus_reopen_period_s").as_in(0.0, 60.0, "s", true);
  const yaml::Reader gripper = root.get("gripper");
  gripper.expect_keys({"min_m", "max_m", "effort_max_nm"});
  d.gripper_min_m = gripper.get("min_m").as_in(0.0, 0.07, "m");
  d.gripper_max_m = gripper.get("max_m").as_in(0.0, 0.07, "m");
  if (d.gripper_max_m < d.gripper_min_m) gripper.get("max_m").fail("must not be below gripper.min_m");
  d.gripper_effort_max_nm = gripper.get("effort_max_nm").as_in(0.0, 5.0, "N m");

  // Joint limits: the robot model's (its URDF), in arm_joints order.
  static_assert(kNumArmJoints == kNumJoints, "the Piper has six joints");
  const RobotModel model = load_robot_model(p.robot_yaml);
  for (int j = 0; j < kNumJoints; ++j) {
    d.lower_rad[j] = model.joints[j].lower_rad;
    d.upper_rad[j] = model.joints[j].upper_rad;
  }
  return p;
}

}  // namespace porter::piper
