#pragma once
// Poses of the robot's rigid bodies from a whole-body configuration, computed for the validator
// from the model's joint origins and axes (independently of the planner's kinematics).
//
// Bodies: 0 = base (link 0), 1..6 = arm links, 7 = gripper (link 7, the EE frame), 8 = payload
// (rigid on link 7; its shapes are given in the EE frame by the grasp T_EE_P). Link j's frame is
// T_L(j-1)_Lj = T_parent_joint_j * Rot(axis_j, q_j); link 7's frame is T_L6_EE in link 6; the base
// frame is T_W_B = (x, y, 0) rotated by yaw about z.
//
// Thread-safety: reentrant.

#include <array>
#include <string>

#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"

namespace porter::validation {

inline constexpr int kNumBodies = kNumLinks + 1;
inline constexpr int kPayloadBody = kNumLinks;

using BodyPoses = std::array<Eigen::Isometry3d, kNumBodies>;

/// Whole-body configuration as the validator uses it.
struct WholeBodyConfig {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  Eigen::Matrix<double, kNumArmJoints, 1> q_rad = Eigen::Matrix<double, kNumArmJoints, 1>::Zero();
};

/// T_W_body for every body (payload body = link 7's frame).
BodyPoses body_poses(const RobotModel& model, const WholeBodyConfig& config);

/// Rotation by angle about a unit axis, as a rotation matrix (Rodrigues).
Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& unit_axis, double angle_rad);

/// Name of a body for reports: the model's link name, or "payload:<name>" for the payload.
std::string body_name(const RobotModel& model, const std::string& payload_name, int body);

/// Whether the pair (a, b) of bodies must be checked for self-collision: the model's allowed
/// matrix for links (adjacent links are allowed there); the payload counts as link 7 and is
/// never checked against link 7 itself, to which it is rigidly attached.
bool self_pair_checked(const RobotModel& model, int a, int b);

}  // namespace porter::validation
