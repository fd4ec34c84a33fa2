#pragma once
// Forward kinematics and point Jacobians of the whole body. Free functions over an immutable
// RobotModel and a caller-owned KinematicsWorkspace; no heap allocation in any call.
//
// Thread-safety: a workspace belongs to one thread; the model may be shared.

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter {

struct KinematicsWorkspace {
  /// Pose of each planning link frame in the world, filled by forward_kinematics().
  std::array<Eigen::Isometry3d, kNumLinks> T_W_L;
  /// Pose in the world of the frame each link's geometry is voxelized in for the chain
  /// decomposition: the parent frame *after* the joint origin but *before* the joint rotation
  /// (T_W_J[j] for j = 1..6); T_W_J[0] is the base frame. Filled by forward_kinematics().
  std::array<Eigen::Isometry3d, kNumLinks> T_W_J;
  /// Joint axes and origins in the world (index j-1 for joint j).
  std::array<Eigen::Vector3d, kNumArmJoints> axis_W;
  std::array<Eigen::Vector3d, kNumArmJoints> origin_W;
};

/// Fills ws.T_W_L, ws.T_W_J, ws.axis_W and ws.origin_W for the configuration.
void forward_kinematics(const RobotModel& model, const RobotConfiguration& config,
                        KinematicsWorkspace& ws);

/// Pose of every link frame relative to the base frame B for arm angles q (base-independent).
void arm_forward_kinematics(const RobotModel& model, const JointVector& q_rad,
                            std::array<Eigen::Isometry3d, kNumLinks>& T_B_L);

/// Linear Jacobian of a point fixed on link `link` (0..7), given by its world position p_W at
/// the configuration last passed to forward_kinematics(), with respect to
/// [x, y, yaw, q1..q6]. Columns of joints that do not move the link are zero.
void point_jacobian(const RobotModel& model, const KinematicsWorkspace& ws, int link,
                    const Eigen::Vector3d& p_W, PointJacobian& J);

}  // namespace porter
