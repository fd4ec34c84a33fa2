#include "porter/validation/chain_kinematics.hpp"

namespace porter::validation {

Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& a, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Eigen::Matrix3d K;
  K << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return Eigen::Matrix3d::Identity() + s * K + (1.0 - c) * (K * K);
}

BodyPoses body_poses(const RobotModel& model, const WholeBodyConfig& config) {
  BodyPoses T;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.linear() = axis_rotation(Eigen::Vector3d::UnitZ(), config.yaw_rad);
  base.translation() = Eigen::Vector3d(config.x_m, config.y_m, 0.0);
  T[0] = base;
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const ArmJoint& joint = model.joints[static_cast<size_t>(j - 1)];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    motion.linear() = axis_rotation(joint.axis.normalized(), config.q_rad[j - 1]);
    T[static_cast<size_t>(j)] = T[static_cast<size_t>(j - 1)] * joint.T_parent_joint * motion;
  }
  T[kNumLinks - 1] = T[kNumArmJoints] * model.T_L6_EE;
  T[kPayloadBody] = T[kNumLinks - 1];
  return T;
}

std::string body_name(const RobotModel& model, const std::string& payload_name, int body) {
  if (body == kPayloadBody) return "payload:" + payload_name;
  if (body < 0 || body >= kNumLinks) return "body " + std::to_string(body);
  const std::string& n = model.links[static_cast<size_t>(body)].name;
  return n.empty() ? "link " + std::to_string(body) : n;
}

bool self_pair_checked(const RobotModel& model, int a, int b) {
  const int la = a == kPayloadBody ? kNumLinks - 1 : a;
  const int lb = b == kPayloadBody ? kNumLinks - 1 : b;
  if (la == lb) return false;
  return !model.allowed_collisions[static_cast<size_t>(la)][static_cast<size_t>(lb)];
}

}  // namespace porter::validation
