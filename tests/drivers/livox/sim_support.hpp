#pragma once
// Shared pieces of the simulated-MID-360 tests: the shipped robot with a payload, a closed
// room, and the sensor mount of the shipped config.

#include <cstdlib>
#include <string>
#include <vector>

#include "porter/core/geometry.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/livox_sim/simulated_mid360.hpp"

namespace porter::livox::test {

inline std::string source_dir() {
  const char* env = std::getenv("PORTER_SOURCE_DIR");
  return env ? env : PORTER_SOURCE_DIR;
}
inline std::string config_path(const std::string& rel) { return source_dir() + "/config/" + rel; }
inline std::string robot_yaml() { return config_path("robots/scout_mini_piper/robot.yaml"); }

/// The shipped robot carrying config/payloads/<payload>.yaml ("" = none).
inline RobotModel robot_with(const std::string& payload) {
  RobotModel robot = load_robot_model(robot_yaml());
  if (!payload.empty()) robot = attach_payload(robot, load_payload(config_path("payloads/" + payload + ".yaml")));
  return robot;
}

inline CollisionShape box(const std::string& name, Eigen::Vector3d center, Eigen::Vector3d size) {
  CollisionShape s;
  s.name = name;
  s.geometry = Box{size};
  s.T_parent_shape.translation() = center;
  return s;
}

/// Walls and a ceiling around [-hx, hx] x [-hy, hy] x [0, h]: every ray from inside returns.
inline std::vector<CollisionShape> closed_room(double hx, double hy, double h) {
  const double t = 0.2;
  return {box("wall +x", {hx + t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}),
          box("wall -x", {-hx - t / 2, 0, h / 2}, {t, 2 * hy + 2 * t, h}),
          box("wall +y", {0, hy + t / 2, h / 2}, {2 * hx + 2 * t, t, h}),
          box("wall -y", {0, -hy - t / 2, h / 2}, {2 * hx + 2 * t, t, h}),
          box("ceiling", {0, 0, h + t / 2}, {2 * hx + 2 * t, 2 * hy + 2 * t, t})};
}

/// Sensor parameters as shipped: the point frame 0.2875 m above the mast link (-0.22, 0, 0.245).
inline sim::Mid360SimParams shipped_params() {
  sim::Mid360SimParams p;
  p.T_B_S = Eigen::Isometry3d::Identity();
  p.T_B_S.translation() = Eigen::Vector3d(-0.22, 0.0, 0.245 + 0.2875);
  return p;
}

/// The arm pose of the shipped scenes' start (config/scenes/empty.yaml).
inline RobotConfiguration start_configuration(double x = 0.0, double y = 0.0, double yaw = 0.0) {
  RobotConfiguration c;
  c.base = {x, y, yaw};
  c.q_rad << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  return c;
}

}  // namespace porter::livox::test
