#pragma once
// Hand-made worlds and trajectories for the validator's tests: the shipped robot and T payload,
// scenes built in code, rest-to-rest quintic pieces.

#include <string>
#include <vector>

#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/scene.hpp"
#include "porter/validation/flat_trajectory.hpp"

namespace porter::validation::test {

inline std::string source_path(const std::string& rel) { return std::string(PORTER_SOURCE_DIR) + "/" + rel; }

inline const RobotModel& robot() {
  static const RobotModel m = load_robot_model(source_path("config/robots/scout_mini_piper/robot.yaml"));
  return m;
}
inline const Payload& t_bar() {
  static const Payload p = load_payload(source_path("config/payloads/t_bar.yaml"));
  return p;
}

/// The scenes' carrying pose of the arm.
inline Eigen::Matrix<double, 6, 1> carry_arm() {
  Eigen::Matrix<double, 6, 1> q;
  q << 0.0, 0.6, -0.9, 0.0, 0.5, 0.0;
  return q;
}

inline FlatVector flat(double x, double y, const Eigen::Matrix<double, 6, 1>& q) {
  FlatVector z;
  z << x, y, q;
  return z;
}

/// Rest-to-rest quintic from z0 to z1 over T: z0 + (z1 - z0) (10 s^3 - 15 s^4 + 6 s^5), s = t / T.
inline PolyPiece ramp(const FlatVector& z0, const FlatVector& z1, double T, int eta = 1) {
  PolyPiece p;
  p.duration_s = T;
  p.eta = eta;
  const FlatVector d = z1 - z0;
  p.coeffs.row(0) = z0.transpose();
  p.coeffs.row(3) = (10.0 * d / std::pow(T, 3)).transpose();
  p.coeffs.row(4) = (-15.0 * d / std::pow(T, 4)).transpose();
  p.coeffs.row(5) = (6.0 * d / std::pow(T, 5)).transpose();
  return p;
}

inline CollisionShape box_obstacle(const std::string& name, const Eigen::Vector3d& min_W,
                                   const Eigen::Vector3d& max_W) {
  CollisionShape s;
  s.name = name;
  s.geometry = Box{max_W - min_W};
  s.T_parent_shape = Eigen::Isometry3d::Identity();
  s.T_parent_shape.translation() = 0.5 * (min_W + max_W);
  return s;
}

/// A scene from (x0, 0, 0) to (x1, 0, 0) with the carrying arm and the given obstacles.
inline Scene line_scene(double x0, double x1, std::vector<CollisionShape> obstacles) {
  Scene s;
  s.name = "test";
  s.bounds_W = Eigen::AlignedBox3d(Eigen::Vector3d(-10, -10, 0), Eigen::Vector3d(10, 10, 3));
  s.start.base = {x0, 0.0, 0.0};
  s.start.q_rad = carry_arm();
  s.goal.base = {x1, 0.0, 0.0};
  s.goal.q_rad = carry_arm();
  s.obstacles = std::move(obstacles);
  return s;
}

/// Straight drive along x with the carrying arm, rest to rest.
inline FlatTrajectory line_trajectory(double x0, double x1, double T) {
  return FlatTrajectory({ramp(flat(x0, 0, carry_arm()), flat(x1, 0, carry_arm()), T)}, 0.0);
}

}  // namespace porter::validation::test
