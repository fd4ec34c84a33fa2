#include "tracker_config.hpp"

#include <cmath>

#include "porter/core/load_error.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter::tracker_app {

TrackerConfig load_tracker_config(const std::string& path) {
  const auto cfg = yaml::Reader::load_file(path);
  cfg.expect_keys({"robot", "frame_id", "loop", "gains", "watchdog", "fault", "arm"});
  TrackerConfig out;
  out.file = path;
  out.robot_file = yaml::resolve_path(path, cfg.get("robot").as_string());
  tracker::TrackerParams& p = out.params;
  p.frame_id = cfg.get("frame_id").as_string();
  if (p.frame_id.empty()) cfg.get("frame_id").fail("must not be empty");

  const auto loop = cfg.get("loop");
  loop.expect_keys({"rate_hz", "status_rate_hz", "sched_fifo", "sched_priority",
                    "stats_log_period_s"});
  out.rate_hz = loop.get("rate_hz").as_positive();
  if (out.rate_hz < 1.0 || out.rate_hz > 1000.0) loop.get("rate_hz").fail("must be in [1, 1000]");
  out.status_rate_hz = loop.get("status_rate_hz").as_positive();
  if (out.status_rate_hz > out.rate_hz) {
    loop.get("status_rate_hz").fail("must not exceed loop.rate_hz");
  }
  out.sched_fifo = loop.get("sched_fifo").as_bool();
  out.sched_priority = loop.get("sched_priority").as_int();
  if (out.sched_priority < 1 || out.sched_priority > 99) {
    loop.get("sched_priority").fail("must be in [1, 99]");
  }
  // At least hourly; the loop counts it in cycles (rate x period).
  out.stats_log_period_s = loop.get("stats_log_period_s").as_in(0.1, 3600.0, "s");
  p.period_s = 1.0 / out.rate_hz;

  const auto gains = cfg.get("gains");
  gains.expect_keys({"k_x_1ps", "k_y_1pm2", "k_yaw_1pm", "k_yaw_rest_1ps"});
  // Up to 100 (1/s, 1/m^2, 1/m): a gain times the control period beyond ~1 makes the sampled
  // loop overshoot; the shipped gains are 0.5-4.
  p.gains.k_x_1ps = gains.get("k_x_1ps").as_in(0.0, 100.0, "1/s", true);
  p.gains.k_y_1pm2 = gains.get("k_y_1pm2").as_in(0.0, 100.0, "1/m^2", true);
  p.gains.k_yaw_1pm = gains.get("k_yaw_1pm").as_in(0.0, 100.0, "1/m");
  p.gains.k_yaw_rest_1ps = gains.get("k_yaw_rest_1ps").as_in(0.0, 100.0, "1/s");

  const auto wd = cfg.get("watchdog");
  wd.expect_keys({"state_timeout_s", "require_arm_state", "trajectory_timeout_s",
                  "trajectory_max_age_s", "max_start_lag_s"});
  // Ages and timeouts up to 10 s (commands from a state or trajectory that old are no control),
  // trajectory_timeout_s up to an hour (0 = off).
  p.state_timeout_s = wd.get("state_timeout_s").as_in(0.0, 10.0, "s", true);
  p.require_arm_state = wd.get("require_arm_state").as_bool();
  p.trajectory_timeout_s = wd.get("trajectory_timeout_s").as_in(0.0, 3600.0, "s");
  p.trajectory_max_age_s = wd.get("trajectory_max_age_s").as_in(0.0, 10.0, "s", true);
  p.max_start_lag_s = wd.get("max_start_lag_s").as_in(0.0, 10.0, "s");
  if (p.state_timeout_s < p.period_s) {
    wd.get("state_timeout_s").fail("must be at least one control period");
  }

  const auto fault = cfg.get("fault");
  fault.expect_keys({"max_position_error_m", "max_yaw_error_rad"});
  // The yaw error is wrapped to [-pi, pi]: a limit above pi would never act.
  p.max_position_error_m = fault.get("max_position_error_m").as_in(0.0, 100.0, "m", true);
  p.max_yaw_error_rad = fault.get("max_yaw_error_rad").as_in(0.0, 3.14159265358979323846, "rad", true);

  const auto arm = cfg.get("arm");
  arm.expect_keys({"speed_pct"});
  out.arm_speed_pct = arm.get("speed_pct").as_positive();
  if (out.arm_speed_pct > 100.0) arm.get("speed_pct").fail("must be in (0, 100]");

  RobotModel robot;
  try {
    robot = load_robot_model(out.robot_file);
  } catch (const LoadError& e) {
    throw LoadError(path, "key 'robot'", e.what());
  }
  p.base_limits = robot.base;
  p.joint_velocity_max_radps = robot.velocity_limits();
  try {
    p.validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path, "", e.what());
  }
  return out;
}

}  // namespace porter::tracker_app
