#include "porter/core/robot_model.hpp"

#include <algorithm>

namespace porter {

JointVector RobotModel::lower_limits() const {
  JointVector v;
  for (int i = 0; i < kNumArmJoints; ++i) v[i] = joints[i].lower_rad;
  return v;
}

JointVector RobotModel::upper_limits() const {
  JointVector v;
  for (int i = 0; i < kNumArmJoints; ++i) v[i] = joints[i].upper_rad;
  return v;
}

JointVector RobotModel::velocity_limits() const {
  JointVector v;
  for (int i = 0; i < kNumArmJoints; ++i) v[i] = joints[i].velocity_max_radps;
  return v;
}

JointVector RobotModel::acceleration_limits() const {
  JointVector v;
  for (int i = 0; i < kNumArmJoints; ++i) v[i] = joints[i].acceleration_max_radps2;
  return v;
}

bool RobotModel::within_joint_limits(const JointVector& q_rad, double tolerance_rad) const {
  for (int i = 0; i < kNumArmJoints; ++i) {
    if (!(q_rad[i] >= joints[i].lower_rad - tolerance_rad && q_rad[i] <= joints[i].upper_rad + tolerance_rad))
      return false;
  }
  return true;
}

void RobotModel::update_link_bounds() {
  for (auto& link : links) {
    link.bounds.setEmpty();
    for (const auto& s : link.shapes) link.bounds.extend(shape_bounds(s));
    if (link.bounds.isEmpty()) {
      link.bounding_center.setZero();
      link.bounding_radius_m = 0.0;
      continue;
    }
    // Centre of the bounding box; radius from the exact farthest point of each shape, so the
    // ball is tight for elongated links (a box diagonal would overestimate).
    link.bounding_center = link.bounds.center();
    double r = 0.0;
    for (const auto& s : link.shapes) r = std::max(r, shape_max_distance(s, link.bounding_center));
    link.bounding_radius_m = r;
  }
}

}  // namespace porter
