#include "sim_config.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "porter/core/yaml_reader.hpp"
#include "porter/livox_sim/sim_config.hpp"

namespace porter::sim {
namespace {

void load_scout_mini(const yaml::Reader& r, scout_mini::FirmwareParams& p) {
  r.expect_keys({"linear_accel_max_mps2", "angular_accel_max_radps2", "time_constant_s",
                 "command_timeout_s", "battery_voltage_v", "gear_ratio", "pulses_per_motor_rev"});
  p.linear_accel_max_mps2 = r.get("linear_accel_max_mps2").as_in(0.01, 50.0, "m/s^2");
  p.angular_accel_max_radps2 = r.get("angular_accel_max_radps2").as_in(0.01, 100.0, "rad/s^2");
  p.time_constant_s = r.get("time_constant_s").as_in(0.0, 2.0, "s");
  p.command_timeout_s = r.get("command_timeout_s").as_in(0.02, 10.0, "s");
  p.battery_voltage_v = r.get("battery_voltage_v").as_in(0.0, 60.0, "V");
  p.gear_ratio = r.get("gear_ratio").as_in(0.01, 1000.0, "");
  p.pulses_per_motor_rev = r.get("pulses_per_motor_rev").as_in(1.0, 1e6, "");
}

void load_piper(const yaml::Reader& r, PiperSimConfig& p) {
  r.expect_keys({"max_speed_radps", "max_accel_radps2", "enable_delay_s", "gripper_max_m",
                 "gripper_speed_mps"});
  p.max_speed_radps = r.get("max_speed_radps").as_in(0.01, 3.0, "rad/s");
  p.max_accel_radps2 = r.get("max_accel_radps2").as_in(0.01, 1000.0, "rad/s^2");
  p.enable_delay_s = r.get("enable_delay_s").as_in(0.0, 5.0, "s");
  p.gripper_max_m = r.get("gripper_max_m").as_in(0.0, 0.2, "m");
  p.gripper_speed_mps = r.get("gripper_speed_mps").as_in(0.001, 1.0, "m/s");
}

std::uint16_t port(const yaml::Reader& r, bool allow_zero) {
  const int p = r.as_int();
  if (p < (allow_zero ? 0 : 1) || p > 65535) {
    r.fail(std::string("must be a port number in [") + (allow_zero ? "0" : "1") + ", 65535]");
  }
  return static_cast<std::uint16_t>(p);
}

void load_lidar(const yaml::Reader& r, const std::string& robot_path, LidarSimConfig& l) {
  r.expect_keys({"enabled", "destination", "point_port", "imu_port", "point_source_port",
                 "imu_source_port", "sensor"});
  l.enabled = r.get("enabled").as_bool();
  l.network.destination = r.get("destination").as_string();
  if (l.network.destination.empty()) r.get("destination").fail("must not be empty");
  l.network.point_port = port(r.get("point_port"), false);
  l.network.imu_port = port(r.get("imu_port"), false);
  l.network.point_source_port = port(r.get("point_source_port"), true);
  l.network.imu_source_port = port(r.get("imu_source_port"), true);
  // Checked (and its mount resolved against the URDF) even when disabled, so a config that
  // turns the LiDAR on later is known to be valid now.
  l.sensor = livox::sim::load_mid360_sim_params(r.get("sensor"), robot_path);
}

}  // namespace

const std::vector<std::string>& known_device_kinds() {
  static const std::vector<std::string> kinds = {"scout_mini", "piper"};
  return kinds;
}

SimConfig load_sim_config(const std::string& path) {
  const yaml::Reader root = yaml::Reader::load_file(path);
  root.expect_keys({"lcm_url", "scene", "scene_seed", "robot", "payload", "step_s", "history_s",
                    "truth_rate_hz", "lio", "arm_joints_rad", "buses", "scout_mini",
                    "piper", "lidar", "status_period_s"});
  SimConfig c;
  c.source = path;
  c.lcm_url = root.get("lcm_url").as_string();
  c.scene_path = yaml::resolve_path(path, root.get("scene").as_string());
  const int seed = root.get("scene_seed").as_int();
  if (seed < 0) root.get("scene_seed").fail("must be >= 0");
  c.scene_seed = static_cast<std::uint64_t>(seed);
  c.robot_path = yaml::resolve_path(path, root.get("robot").as_string());
  const std::string payload = root.get("payload").as_string();
  if (payload == "none") {
    c.payload_path.clear();
  } else if (payload == "scene") {
    c.payload_path = "scene";
  } else {
    c.payload_path = yaml::resolve_path(path, payload);
  }
  c.step_s = root.get("step_s").as_in(1e-4, 0.02, "s");
  c.history_s = root.get("history_s").as_in(0.1, 60.0, "s");
  c.truth_rate_hz = root.get("truth_rate_hz").as_in(1.0, 1000.0, "Hz");
  if (c.truth_rate_hz * c.step_s > 1.0 + 1e-9) {
    root.get("truth_rate_hz").fail("faster than the simulation step (1 / step_s)");
  }
  const yaml::Reader lio = root.get("lio");
  lio.expect_keys({"rate_hz", "position_noise_m", "yaw_noise_rad", "seed"});
  c.lio_rate_hz = lio.get("rate_hz").as_in(1.0, 1000.0, "Hz");
  c.lio_noise.position_sigma_m = lio.get("position_noise_m").as_in(0.0, 10.0, "m");
  c.lio_noise.yaw_sigma_rad = lio.get("yaw_noise_rad").as_in(0.0, 3.2, "rad");
  const int lio_seed = lio.get("seed").as_int();
  if (lio_seed < 0) lio.get("seed").fail("must be >= 0");
  c.lio_noise.seed = static_cast<std::uint64_t>(lio_seed);

  const yaml::Reader arm = root.get("arm_joints_rad");
  if (arm.is_scalar()) {
    if (arm.as_string() != "scene") arm.fail("expected 'scene' or a list of 6 angles (rad)");
  } else {
    const std::vector<double> q = arm.as_doubles(kNumArmJoints);
    for (const double a : q)
      if (!(std::abs(a) <= 6.283185307179586)) arm.fail("angles must be within [-2 pi, 2 pi] rad");
    JointVector v;
    for (int i = 0; i < kNumArmJoints; ++i) v[i] = q[static_cast<std::size_t>(i)];
    c.arm_joints_rad = v;
  }

  const yaml::Reader buses = root.get("buses");
  if (!buses.is_sequence()) buses.fail("expected a list of buses");
  std::set<std::string> bus_names;
  std::set<std::string> device_names;
  for (std::size_t i = 0; i < buses.size(); ++i) {
    const yaml::Reader b = buses.at(i);
    b.expect_keys({"name", "can", "devices"});
    BusConfig bus;
    bus.name = b.get("name").as_string();
    if (bus.name.empty() || !bus_names.insert(bus.name).second) {
      b.get("name").fail("bus names must be unique and not empty");
    }
    bus.can = b.get("can").as_string();
    if (bus.can.find(':') == std::string::npos) {
      b.get("can").fail("expected TRANSPORT:TARGET (lcm:CAN_BASE, memory:NAME, ...)");
    }
    bus.devices = b.get("devices").as_strings();
    for (std::size_t k = 0; k < bus.devices.size(); ++k) {
      const std::string& kind = bus.devices[k];
      const auto& known = known_device_kinds();
      if (std::find(known.begin(), known.end(), kind) == known.end()) {
        std::string list;
        for (const std::string& n : known) list += (list.empty() ? "" : ", ") + n;
        b.get("devices").at(k).fail("unknown device '" + kind + "' (known: " + list + ")");
      }
      if (!device_names.insert(kind).second) {
        b.get("devices").at(k).fail("device '" + kind + "' is hosted twice");
      }
    }
    c.buses.push_back(bus);
  }
  load_scout_mini(root.get("scout_mini"), c.scout_mini);
  load_piper(root.get("piper"), c.piper);
  load_lidar(root.get("lidar"), c.robot_path, c.lidar);
  c.status_period_s = root.get("status_period_s").as_in(1.0, 3600.0, "s");
  return c;
}

}  // namespace porter::sim
