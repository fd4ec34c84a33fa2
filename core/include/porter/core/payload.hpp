#pragma once
// A payload rigidly grasped by the gripper, and attaching it to a robot model as part of
// planning link 7.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/robot_model.hpp"

namespace porter {

struct Payload {
  std::string name;
  std::string source;                      ///< YAML it came from
  std::vector<CollisionShape> shapes;      ///< in the payload frame P
  Eigen::Isometry3d T_EE_P = Eigen::Isometry3d::Identity();  ///< grasp: P in the EE frame
};

/// A copy of `robot` with the payload's shapes added to link 7 (in the EE frame) and the link
/// bounds recomputed. Attaching to a model that already carries a payload replaces nothing:
/// the shapes add up, so attach to the bare model.
RobotModel attach_payload(const RobotModel& robot, const Payload& payload);

}  // namespace porter
