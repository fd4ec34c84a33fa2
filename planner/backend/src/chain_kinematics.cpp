#include "porter/backend/chain_kinematics.hpp"

#include <cmath>

namespace porter::backend {

ChainKinematics::ChainKinematics(const RobotModel& model) {
  for (int j = 0; j < kNumArmJoints; ++j) {
    const ArmJoint& joint = model.joints[static_cast<std::size_t>(j)];
    R_parent_joint_[static_cast<std::size_t>(j)] = joint.T_parent_joint.linear();
    t_parent_joint_[static_cast<std::size_t>(j)] = joint.T_parent_joint.translation();
    axis_[static_cast<std::size_t>(j)] = joint.axis;
  }
  R_L6_EE_ = model.T_L6_EE.linear();
  t_L6_EE_ = model.T_L6_EE.translation();
}

void ChainKinematics::compute(const RobotConfiguration& config, int up_to_link, Workspace& ws) const {
  const double c0 = std::cos(config.base.yaw_rad), s0 = std::sin(config.base.yaw_rad);
  ws.R_W_L[0] << c0, -s0, 0.0, s0, c0, 0.0, 0.0, 0.0, 1.0;
  ws.t_W_L[0] = Eigen::Vector3d(config.base.x_m, config.base.y_m, 0.0);
  const int arm_links = up_to_link < kNumArmJoints ? up_to_link : kNumArmJoints;
  for (int j = 1; j <= arm_links; ++j) {
    const auto i = static_cast<std::size_t>(j - 1);
    const Eigen::Matrix3d& R_prev = ws.R_W_L[i];
    const Eigen::Matrix3d R_joint = R_prev * R_parent_joint_[i];
    ws.origin_W[i] = R_prev * t_parent_joint_[i] + ws.t_W_L[i];
    ws.axis_W[i] = R_joint * axis_[i];
    // Rodrigues rotation about the unit axis a by q.
    const Eigen::Vector3d& a = axis_[i];
    const double q = config.q_rad[static_cast<Eigen::Index>(i)];
    const double c = std::cos(q), s = std::sin(q), t = 1.0 - c;
    Eigen::Matrix3d R;
    R << t * a.x() * a.x() + c, t * a.x() * a.y() - s * a.z(), t * a.x() * a.z() + s * a.y(),
        t * a.x() * a.y() + s * a.z(), t * a.y() * a.y() + c, t * a.y() * a.z() - s * a.x(),
        t * a.x() * a.z() - s * a.y(), t * a.y() * a.z() + s * a.x(), t * a.z() * a.z() + c;
    ws.R_W_L[i + 1].noalias() = R_joint * R;
    ws.t_W_L[i + 1] = ws.origin_W[i];
  }
  if (up_to_link >= kEndEffectorLink) {
    ws.R_W_L[kEndEffectorLink].noalias() = ws.R_W_L[kNumArmJoints] * R_L6_EE_;
    ws.t_W_L[kEndEffectorLink] = ws.R_W_L[kNumArmJoints] * t_L6_EE_ + ws.t_W_L[kNumArmJoints];
  }
  ws.up_to = up_to_link;
}

void ChainKinematics::point_jacobian(const Workspace& ws, int link, const Eigen::Vector3d& p_W,
                                     PointJacobian& J) {
  J.setZero();
  J(0, 0) = 1.0;
  J(1, 1) = 1.0;
  const Eigen::Vector3d r_base = p_W - ws.t_W_L[0];
  J(0, 2) = -r_base.y();
  J(1, 2) = r_base.x();
  const int moving = link >= kEndEffectorLink ? kNumArmJoints : link;
  for (int j = 0; j < moving; ++j) {
    J.col(3 + j) = ws.axis_W[static_cast<std::size_t>(j)].cross(p_W - ws.origin_W[static_cast<std::size_t>(j)]);
  }
}

}  // namespace porter::backend
