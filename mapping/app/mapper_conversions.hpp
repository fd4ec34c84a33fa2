#pragma once
// porter-mapper's one adapter between lcmtypes and the mapping library's types.
//
// Failure: a message that does not make sense (a cloud whose arrays disagree with num_points, a
// negative time offset, non-finite state) returns false with `why` set; nothing throws.

#include <string>

#include "porter/mapping/mapper.hpp"
#include "porter/mapping/octomap_binary.hpp"
#include "porter/octomap_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/robot_state_t.hpp"

namespace porter::mapping::app {

bool to_sensor_cloud(const porter::point_cloud_t& msg, SensorCloud& out, std::string& why);
/// A ROBOT_STATE as the state buffer takes it: the base pose at `utime`, and the joint angles
/// (when the message has them) at their own time, arm_utime (utime when arm_utime is 0).
struct StateSample {
  std::int64_t utime = 0;
  BasePose base;
  bool has_arm = false;          ///< num_joints was 0: the arm is not known yet
  std::int64_t arm_utime = 0;
  JointVector q_rad = JointVector::Zero();
};
bool to_state_sample(const porter::robot_state_t& msg, StateSample& out, std::string& why);

/// The MAP_OCTOMAP message of `map` (binary stream, written by `writer`, which follows this
/// map), stamped with the last integrated scan.
void to_map_message(const RollingMap& map, const FilteredCloud& last, const std::string& frame_id,
                    std::int64_t map_id, OctomapBinaryWriter& writer, porter::octomap_t& out);

}  // namespace porter::mapping::app
