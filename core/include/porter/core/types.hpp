#pragma once
// Fixed dimensions of the planning problem and the small value types shared by every module.
//
// Conventions (see README "Frames and units"):
//   - W is the world frame (z up, gravity -z), B the base frame (origin on the ground under the
//     base's rotation centre, x forward), Lj the frame of planning link j, EE the end-effector
//     frame, P a payload's own frame.
//   - T_A_B is the pose of frame B expressed in frame A (maps points in B to points in A).
//   - Units are SI and carried in names: _m, _rad, _s, _mps, _radps, _radps2.

#include <array>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace porter {

/// Revolute joints in the arm. Porter plans for 6-joint arms; the URDF loader refuses others.
inline constexpr int kNumArmJoints = 6;
/// Planning links: 0 = base, 1..6 = arm links, 7 = gripper + payload (no joint of its own).
inline constexpr int kNumLinks = kNumArmJoints + 2;
inline constexpr int kEndEffectorLink = kNumLinks - 1;
/// Whole-body configuration coordinates used by Jacobians: [x, y, yaw, q1..q6].
inline constexpr int kNumDof = 3 + kNumArmJoints;
/// Flat-output dimension of trajectories: z = [p_x, p_y, q1..q6].
inline constexpr int kTrajDim = 2 + kNumArmJoints;

using JointVector = Eigen::Matrix<double, kNumArmJoints, 1>;
using DofVector = Eigen::Matrix<double, kNumDof, 1>;
using TrajVector = Eigen::Matrix<double, kTrajDim, 1>;
/// Geometric (linear part only) Jacobian of a point: d p_W / d [x, y, yaw, q1..q6].
using PointJacobian = Eigen::Matrix<double, 3, kNumDof>;

/// Planar pose of the base in the world: position of B's origin and heading of B's x axis.
struct BasePose {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;

  Eigen::Isometry3d T_W_B() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(x_m, y_m, 0.0);
    return T;
  }
};

/// A whole-body configuration: base pose plus arm joint angles.
struct RobotConfiguration {
  BasePose base;
  JointVector q_rad = JointVector::Zero();

  DofVector as_dof() const {
    DofVector v;
    v << base.x_m, base.y_m, base.yaw_rad, q_rad;
    return v;
  }
  static RobotConfiguration from_dof(const DofVector& v) {
    RobotConfiguration c;
    c.base = {v[0], v[1], v[2]};
    c.q_rad = v.tail<kNumArmJoints>();
    return c;
  }
};

}  // namespace porter
