#include "porter/core/kinematics.hpp"

namespace porter {

namespace {

// Rotation by angle q about a unit axis (Rodrigues), written out to avoid AngleAxis's
// normalisation and temporaries in the hot path.
inline Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& a, double q) {
  const double c = std::cos(q), s = std::sin(q), t = 1.0 - c;
  Eigen::Matrix3d R;
  R << t * a.x() * a.x() + c, t * a.x() * a.y() - s * a.z(), t * a.x() * a.z() + s * a.y(),
      t * a.x() * a.y() + s * a.z(), t * a.y() * a.y() + c, t * a.y() * a.z() - s * a.x(),
      t * a.x() * a.z() - s * a.y(), t * a.y() * a.z() + s * a.x(), t * a.z() * a.z() + c;
  return R;
}

inline Eigen::Isometry3d joint_motion(const ArmJoint& joint, double q) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = axis_rotation(joint.axis, q);
  return T;
}

}  // namespace

void forward_kinematics(const RobotModel& model, const RobotConfiguration& config,
                        KinematicsWorkspace& ws) {
  ws.T_W_L[0] = config.base.T_W_B();
  ws.T_W_J[0] = ws.T_W_L[0];
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const ArmJoint& joint = model.joints[j - 1];
    ws.T_W_J[j] = ws.T_W_L[j - 1] * joint.T_parent_joint;
    ws.T_W_L[j] = ws.T_W_J[j] * joint_motion(joint, config.q_rad[j - 1]);
    ws.axis_W[j - 1] = ws.T_W_J[j].linear() * joint.axis;
    ws.origin_W[j - 1] = ws.T_W_J[j].translation();
  }
  ws.T_W_L[kEndEffectorLink] = ws.T_W_L[kNumArmJoints] * model.T_L6_EE;
  ws.T_W_J[kEndEffectorLink] = ws.T_W_L[kEndEffectorLink];
}

void arm_forward_kinematics(const RobotModel& model, const JointVector& q_rad,
                            std::array<Eigen::Isometry3d, kNumLinks>& T_B_L) {
  T_B_L[0] = Eigen::Isometry3d::Identity();
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const ArmJoint& joint = model.joints[j - 1];
    T_B_L[j] = T_B_L[j - 1] * joint.T_parent_joint * joint_motion(joint, q_rad[j - 1]);
  }
  T_B_L[kEndEffectorLink] = T_B_L[kNumArmJoints] * model.T_L6_EE;
}

void point_jacobian(const RobotModel& model, const KinematicsWorkspace& ws, int link,
                    const Eigen::Vector3d& p_W, PointJacobian& J) {
  J.setZero();
  // Base translation moves every point one-to-one in x and y.
  J(0, 0) = 1.0;
  J(1, 1) = 1.0;
  // Base yaw rotates about the world z axis through the base origin.
  const Eigen::Vector3d r_base = p_W - ws.T_W_L[0].translation();
  J(0, 2) = -r_base.y();
  J(1, 2) = r_base.x();
  const int moving_joints = link >= kEndEffectorLink ? kNumArmJoints : link;
  for (int j = 0; j < moving_joints; ++j) {
    J.col(3 + j) = ws.axis_W[j].cross(p_W - ws.origin_W[j]);
  }
}

}  // namespace porter
