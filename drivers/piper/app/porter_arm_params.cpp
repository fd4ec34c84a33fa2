#include "porter_arm_params.hpp"

#include <cstdio>

#include "porter/core/robot_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::piper {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

double in_range(const yaml::Reader& r, double lo, double hi, bool lo_open) {
  const double v = r.as_double();
  if (!(lo_open ? v > lo : v >= lo) || !(v <= hi)) {
    r.fail("expected a number in " + std::string(lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + "], got " +
           num(v));
  }
  return v;
}

}  // namespace

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
  p.loop_rate_hz = in_range(root.get("loop_rate_hz"), 10.0, 1000.0, false);
  ArmDriverParams& d = p.driver;
  d.cmd_timeout_s = in_range(root.get("cmd_timeout_s"), 0.0, 10.0, true);
  d.link_timeout_s = in_range(root.get("link_timeout_s"), 0.0, 5.0, true);
  d.motor_feedback_timeout_s = in_range(root.get("motor_feedback_timeout_s"), 0.0, 5.0, true);
  d.retry_period_s = in_range(root.get("retry_period_s"), 0.0, 5.0, true);
  d.shutdown_timeout_s = in_range(root.get("shutdown_timeout_s"), 0.0, 10.0, false);
  const yaml::Reader speed = root.get("default_speed_pct");
  d.default_speed_pct = speed.as_int();
  if (d.default_speed_pct < 1 || d.default_speed_pct > 100) {
    speed.fail("expected an integer in [1, 100], got " + std::to_string(d.default_speed_pct));
  }
  p.bus_reopen_period_s = in_range(root.get("bus_reopen_period_s"), 0.0, 60.0, true);
  const yaml::Reader gripper = root.get("gripper");
  gripper.expect_keys({"min_m", "max_m", "effort_max_nm"});
  d.gripper_min_m = in_range(gripper.get("min_m"), 0.0, 0.07, false);
  d.gripper_max_m = in_range(gripper.get("max_m"), 0.0, 0.07, false);
  if (d.gripper_max_m < d.gripper_min_m) gripper.get("max_m").fail("must not be below gripper.min_m");
  d.gripper_effort_max_nm = in_range(gripper.get("effort_max_nm"), 0.0, 5.0, false);

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
