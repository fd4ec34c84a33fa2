#include "base_config.hpp"

#include <cstdio>

#include "porter/core/robot_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::scout_mini {
namespace {

// The Scout Mini firmware's own yaw-rate limit (ugv_sdk ScoutMiniLimits).
constexpr double kFirmwareOmegaMax = 2.5235;

}  // namespace

BaseNodeConfig load_base_config(const std::string& path) {
  const yaml::Reader root = yaml::Reader::load_file(path);
  root.expect_keys({"can_bus", "lcm_url", "robot", "command_rate_hz", "command_stale_s",
                    "v_max_mps", "omega_max_radps", "feedback_timeout_s", "mode_retry_period_s",
                    "odometry_jump_m", "stats_period_s", "realtime_priority"});
  BaseNodeConfig c;
  c.source = path;
  c.can_bus = root.get("can_bus").as_string();
  if (c.can_bus.find(':') == std::string::npos) {
    root.get("can_bus").fail("expected TRANSPORT:TARGET (socketcan:can0, "
                             "slcan:/dev/ttyACM0@500000, lcm:CAN_BASE, memory:NAME)");
  }
  c.lcm_url = root.get("lcm_url").as_string();
  c.robot_config = yaml::resolve_path(path, root.get("robot").as_string());
  const RobotModel robot = load_robot_model(c.robot_config);

  DriverParams& d = c.driver;
  d.track_width_m = robot.base.track_width_m;
  d.wheel_radius_m = robot.base.wheel_radius_m;
  d.wheel_omega_max_radps = robot.base.wheel_omega_max_radps;
  const double rate = root.get("command_rate_hz").as_in(20.0, 200.0, "Hz");
  d.command_period_s = 1.0 / rate;
  d.command_stale_s = root.get("command_stale_s").as_in(2.0 * d.command_period_s, 0.5, "s");
  const double wheel_v_max = d.wheel_omega_max_radps * d.wheel_radius_m;
  d.v_max_mps = root.get("v_max_mps").as_positive();
  if (d.v_max_mps > wheel_v_max + 1e-9) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "%g m/s exceeds the robot's wheel-speed limit %g m/s (%s: base."
                  "wheel_omega_max_radps x base.wheel_radius_m)",
                  d.v_max_mps, wheel_v_max, c.robot_config.c_str());
    root.get("v_max_mps").fail(buf);
  }
  d.omega_max_radps = root.get("omega_max_radps").as_in(1e-3, kFirmwareOmegaMax, "rad/s");
  d.feedback_timeout_s = root.get("feedback_timeout_s").as_in(0.05, 5.0, "s");
  d.mode_retry_period_s = root.get("mode_retry_period_s").as_in(0.02, 5.0, "s");
  d.odometry_jump_m = root.get("odometry_jump_m").as_in(0.01, 10.0, "m");
  c.stats_period_s = root.get("stats_period_s").as_in(1.0, 3600.0, "s");
  c.realtime_priority = static_cast<int>(root.get("realtime_priority").as_in(0, 99, ""));
  if (c.realtime_priority != root.get("realtime_priority").as_int()) {
    root.get("realtime_priority").fail("expected an integer");
  }
  return c;
}

}  // namespace porter::scout_mini
