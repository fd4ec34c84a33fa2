#include "porter/piper/piper_dh.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace porter::piper {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr std::array<double, 6> kA_m = {0.0, 0.0, 0.28503, -0.02198, 0.0, 0.0};
constexpr std::array<double, 6> kAlpha_rad = {0.0, -90.0 * kDeg, 0.0, 90.0 * kDeg, -90.0 * kDeg, 90.0 * kDeg};
constexpr std::array<double, 6> kD_m = {0.123, 0.0, 0.0, 0.25075, 0.0, 0.091};
constexpr std::array<double, 6> kOffset_rad = {0.0, -172.22 * kDeg, -102.78 * kDeg, 0.0, 0.0, 0.0};
}  // namespace

FlangePose piper_flange_pose(const std::array<double, 6>& q_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 6; ++i) {
    T = T * Eigen::AngleAxisd(kAlpha_rad[i], Eigen::Vector3d::UnitX()) *
        Eigen::Translation3d(kA_m[i], 0.0, 0.0) *
        Eigen::AngleAxisd(q_rad[i] + kOffset_rad[i], Eigen::Vector3d::UnitZ()) *
        Eigen::Translation3d(0.0, 0.0, kD_m[i]);
  }
  FlangePose pose;
  const Eigen::Matrix3d R = T.linear();
  for (int k = 0; k < 3; ++k) pose.p_m[k] = T.translation()[k];
  // Z-Y-X Euler angles; at pitch = ±90° yaw is set to 0 and the rotation goes into roll.
  const double cos_pitch = std::hypot(R(0, 0), R(1, 0));
  pose.rpy_rad[1] = std::atan2(-R(2, 0), cos_pitch);
  if (cos_pitch > 1e-9) {
    pose.rpy_rad[0] = std::atan2(R(2, 1), R(2, 2));
    pose.rpy_rad[2] = std::atan2(R(1, 0), R(0, 0));
  } else {
    pose.rpy_rad[0] = std::atan2(-R(1, 2), R(1, 1));
    pose.rpy_rad[2] = 0.0;
  }
  return pose;
}

}  // namespace porter::piper
