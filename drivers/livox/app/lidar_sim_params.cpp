#include "lidar_sim_params.hpp"

#include <cmath>

#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene_loader.hpp"
#include "porter/core/yaml_reader.hpp"
#include "porter/livox_sim/sim_config.hpp"

namespace porter::livox::app {
namespace {

std::uint16_t port(const yaml::Reader& r, bool allow_zero) {
  const int p = r.as_int();
  if (p < (allow_zero ? 0 : 1) || p > 65535) r.fail("must be a port number in [" + std::string(allow_zero ? "0" : "1") + ", 65535]");
  return static_cast<std::uint16_t>(p);
}

}  // namespace

LidarSimSetup load_lidar_sim_setup(const std::string& path) {
  const yaml::Reader root = yaml::Reader::load_file(path);
  root.expect_keys({"robot", "scene", "payload", "motion", "network", "step_period_s",
                    "duration_s", "sensor"});
  LidarSimSetup s;
  s.robot_file = yaml::resolve_path(path, root.get("robot").as_string());
  s.scene_file = yaml::resolve_path(path, root.get("scene").as_string());
  s.robot = load_robot_model(s.robot_file);
  s.scene = load_scene(s.scene_file);

  const yaml::Reader payload = root.get("payload");
  const std::string payload_key = payload.as_string();
  if (payload_key == "scene") {
    s.payload_file = s.scene.payload_file;
  } else if (payload_key != "none") {
    s.payload_file = yaml::resolve_path(path, payload_key);
  }
  if (!s.payload_file.empty()) s.robot = attach_payload(s.robot, load_payload(s.payload_file));

  const yaml::Reader motion = root.get("motion");
  motion.expect_keys({"loop", "waypoints"});
  s.loop = motion.get("loop").as_bool();
  const yaml::Reader wps = motion.get("waypoints");
  for (std::size_t i = 0; i < wps.size(); ++i) {
    const yaml::Reader row = wps.at(i);
    const auto v = row.as_doubles(10);
    // Times within ~28 h, positions within 10 km, angles within 1e4 rad: the motion is
    // interpolated between them and sampled at every step.
    for (const double x : v)
      if (!(std::abs(x) <= 1e4)) row.fail("values must be within [-1e4, 1e4] (s, m, rad)");
    sim::Waypoint w;
    w.t_s = v[0];
    w.config.base = {v[1], v[2], v[3]};
    for (int j = 0; j < 6; ++j) w.config.q_rad[j] = v[4 + j];
    if (!s.waypoints.empty() && !(w.t_s > s.waypoints.back().t_s)) {
      row.fail("waypoint times must increase");
    }
    s.waypoints.push_back(w);
  }
  if (s.waypoints.empty()) s.waypoints.push_back({0.0, s.scene.start});

  const yaml::Reader net = root.get("network");
  net.expect_keys({"destination", "point_port", "imu_port", "point_source_port", "imu_source_port",
                   "command_port", "sampling_at_start"});
  s.network.destination = net.get("destination").as_string();
  s.network.point_port = port(net.get("point_port"), false);
  s.network.imu_port = port(net.get("imu_port"), false);
  s.network.point_source_port = port(net.get("point_source_port"), true);
  s.network.imu_source_port = port(net.get("imu_source_port"), true);
  s.command_port = port(net.get("command_port"), true);
  s.sampling_at_start = net.get("sampling_at_start").as_bool();

  const yaml::Reader step = root.get("step_period_s");
  s.step_period_s = step.as_in(1e-4, 0.1, "s");
  s.duration_s = root.get("duration_s").as_in(0.0, 1e6, "s");
  s.sensor = sim::load_mid360_sim_params(root.get("sensor"), s.robot_file);
  return s;
}

}  // namespace porter::livox::app
