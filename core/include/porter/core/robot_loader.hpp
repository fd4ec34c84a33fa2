#pragma once
// Builds a RobotModel from a robot config (config/robots/<name>/robot.yaml) and the URDF it
// names. Part of porter::core_io (urdfdom, assimp, yaml-cpp).
//
// The URDF is read with urdfdom. Collision geometry may be boxes, cylinders, spheres or meshes
// (any format assimp reads, with scale). URDF links are grouped into planning links:
//   - every link reached from the root through fixed joints only   -> link 0 (base),
//   - the child of arm joint j and its fixed descendants            -> link j,
//   - end_effector.link and all its descendants                     -> link 7 (expressed in
//     the end_effector.frame link's frame).
// Movable joints that are not arm joints must be listed under frozen_joints.
//
// Throws LoadError (file, element, reason) for: a missing or unparsable file, an unknown or
// missing key, an arm joint that is missing or not revolute, joints out of chain order (a
// broken chain), an unsupported joint type (floating, planar, or movable and not frozen), a
// base_link that is not the URDF root, an unreadable mesh, and non-physical limits. A URDF
// urdfdom refuses is reported with urdfdom's own reason.
//
// Ranges (docs/hardening.md): URDF origins and collision sizes finite, sizes > 0, and every
// collision shape within kRobotMaxReach_m of its planning link's frame (the planner sizes
// kernels and distance grids from this extent); movable joint axes finite and non-zero; arm
// joint limits within +-kRobotMaxJointAngle_rad and velocities up to
// kRobotMaxJointVelocity_radps; base parameters within the ranges in robot_loader.cpp
// (e.g. wheel_radius_m in [1 mm, 2 m], min_turning_radius_m in [1 mm, 100 m]).

#include <string>

#include "porter/core/robot_model.hpp"

namespace porter {

inline constexpr double kRobotMaxReach_m = 5.0;
inline constexpr double kRobotMaxJointAngle_rad = 2.0 * 3.14159265358979323846;
inline constexpr double kRobotMaxJointVelocity_radps = 100.0;

RobotModel load_robot_model(const std::string& robot_yaml_path);

}  // namespace porter
