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
// base_link that is not the URDF root, an unreadable mesh, and non-physical limits.

#include <string>

#include "porter/core/robot_model.hpp"

namespace porter {

RobotModel load_robot_model(const std::string& robot_yaml_path);

}  // namespace porter
