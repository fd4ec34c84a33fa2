#pragma once
// The immutable description of the mobile manipulator (pinocchio-style Model; the mutable
// per-query state lives in KinematicsWorkspace, see kinematics.hpp).
//
// Planning links: 0 = base (its "joint" is the planar base pose), 1..6 = arm links moved by
// joints 1..6, 7 = gripper + payload, rigidly attached to link 6 (no joint).
// Built once by load_robot_model() (robot_loader.hpp) from config/robots/<name>/robot.yaml and
// its URDF; a payload is attached with attach_payload() (payload.hpp). Thread-safe to share.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/types.hpp"

namespace porter {

/// Arm joint j (1-based in the text, index j-1 here): a revolute joint that moves link j,
/// located in the frame of link j-1 (for joint 1, the base frame B, mount pose included).
struct ArmJoint {
  std::string name;
  Eigen::Isometry3d T_parent_joint = Eigen::Isometry3d::Identity();  ///< joint frame in link j-1
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();                    ///< unit, joint frame
  double lower_rad = 0.0;
  double upper_rad = 0.0;
  double velocity_max_radps = 0.0;
  double acceleration_max_radps2 = 0.0;
};

/// A planning link: all the collision geometry that moves rigidly with it, in its own frame.
struct Link {
  std::string name;                       ///< URDF link that defines the frame
  std::vector<CollisionShape> shapes;     ///< in the link frame
  Eigen::AlignedBox3d bounds;             ///< of all shapes, link frame (empty if no shapes)
  Eigen::Vector3d bounding_center = Eigen::Vector3d::Zero();  ///< link frame
  double bounding_radius_m = 0.0;         ///< all geometry within this ball around the centre
};

/// Differential-drive base parameters (paper eq. 1). The Scout Mini is skid-steer; it is
/// modelled as diff-drive with an effective track width.
struct BaseLimits {
  double wheel_radius_m = 0.0;
  double track_width_m = 0.0;             ///< d_w in the paper
  double wheel_omega_max_radps = 0.0;     ///< |ω_l|, |ω_r| bound
  double wheel_alpha_max_radps2 = 0.0;    ///< |α_l|, |α_r| bound
  double min_turning_radius_m = 0.0;      ///< used by the front-end's motion primitives
  double nonsingular_speed_mps = 0.0;     ///< v_ns: speed kept at gear switches so yaw is defined
};

/// Pairs of planning links that are allowed to touch (adjacent along the chain or always
/// overlapping by construction). Every other pair is checked for self-collision.
using AllowedCollisionMatrix = std::array<std::array<bool, kNumLinks>, kNumLinks>;

class RobotModel {
 public:
  std::string name;
  std::string source;                        ///< robot.yaml it came from
  std::array<Link, kNumLinks> links;
  std::array<ArmJoint, kNumArmJoints> joints;
  Eigen::Isometry3d T_L6_EE = Eigen::Isometry3d::Identity();  ///< link 7's frame in link 6
  BaseLimits base;
  AllowedCollisionMatrix allowed_collisions{};
  std::string payload_name;                  ///< empty when no payload is attached

  JointVector lower_limits() const;
  JointVector upper_limits() const;
  JointVector velocity_limits() const;
  JointVector acceleration_limits() const;
  bool within_joint_limits(const JointVector& q_rad, double tolerance_rad = 0.0) const;

  /// Recomputes bounds, bounding spheres of every link from its shapes. Loaders call it.
  void update_link_bounds();
};

}  // namespace porter
