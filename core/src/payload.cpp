#include "porter/core/payload.hpp"

namespace porter {

RobotModel attach_payload(const RobotModel& robot, const Payload& payload) {
  RobotModel out = robot;
  Link& ee = out.links[kEndEffectorLink];
  for (const CollisionShape& s : payload.shapes) {
    CollisionShape placed = s;
    placed.T_parent_shape = payload.T_EE_P * s.T_parent_shape;
    placed.name = "payload '" + payload.name + "'/" + s.name;
    ee.shapes.push_back(std::move(placed));
  }
  out.payload_name = out.payload_name.empty() ? payload.name : out.payload_name + "+" + payload.name;
  out.update_link_bounds();
  return out;
}

}  // namespace porter
