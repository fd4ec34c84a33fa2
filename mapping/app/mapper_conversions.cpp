#include "mapper_conversions.hpp"

#include <cmath>

#include "porter/mapping/octomap_binary.hpp"

namespace porter::mapping::app {

namespace {
// Times are µs since the epoch; anything past year ~2200 is corrupt (and would overflow sums).
constexpr std::int64_t kMaxUtime = std::int64_t{1} << 53;
}  // namespace

bool to_sensor_cloud(const porter::point_cloud_t& msg, SensorCloud& out, std::string& why) {
  const auto n = static_cast<std::size_t>(msg.num_points);
  if (msg.num_points < 0 || msg.x_m.size() != n || msg.y_m.size() != n || msg.z_m.size() != n ||
      msg.time_offset_ns.size() != n) {
    why = "cloud arrays disagree with num_points " + std::to_string(msg.num_points);
    return false;
  }
  if (msg.utime < 0 || msg.utime > kMaxUtime) {
    why = "utime " + std::to_string(msg.utime) + " out of range";
    return false;
  }
  for (std::int32_t t : msg.time_offset_ns) {
    if (t < 0) {
      why = "negative point time offset " + std::to_string(t) + " ns";
      return false;
    }
  }
  out.utime = msg.utime;
  out.x_m = msg.x_m;
  out.y_m = msg.y_m;
  out.z_m = msg.z_m;
  out.time_offset_ns = msg.time_offset_ns;
  return true;
}

bool to_state_sample(const porter::robot_state_t& msg, StateSample& out, std::string& why) {
  if (msg.utime < 0 || msg.utime > kMaxUtime) {
    why = "utime " + std::to_string(msg.utime) + " out of range";
    return false;
  }
  if (msg.arm_utime < 0 || msg.arm_utime > kMaxUtime) {
    why = "arm_utime " + std::to_string(msg.arm_utime) + " out of range";
    return false;
  }
  if (!std::isfinite(msg.x_m) || !std::isfinite(msg.y_m) || !std::isfinite(msg.yaw_rad)) {
    why = "non-finite base pose";
    return false;
  }
  if (msg.num_joints != 0 && msg.num_joints != kNumArmJoints) {
    why = "num_joints " + std::to_string(msg.num_joints) + " (expected 0 or " + std::to_string(kNumArmJoints) + ")";
    return false;
  }
  if (static_cast<std::size_t>(msg.num_joints) != msg.q_rad.size()) {
    why = "q_rad size disagrees with num_joints";
    return false;
  }
  out.utime = msg.utime;
  out.base = {msg.x_m, msg.y_m, msg.yaw_rad};
  out.has_arm = msg.num_joints == kNumArmJoints;
  out.arm_utime = msg.arm_utime != 0 ? msg.arm_utime : msg.utime;
  out.q_rad.setZero();
  for (int j = 0; j < msg.num_joints; ++j) {
    if (!std::isfinite(msg.q_rad[static_cast<std::size_t>(j)])) {
      why = "non-finite joint angle";
      return false;
    }
    out.q_rad[j] = msg.q_rad[static_cast<std::size_t>(j)];
  }
  return true;
}

void to_map_message(const RollingMap& map, const FilteredCloud& last, const std::string& frame_id,
                    std::int64_t map_id, OctomapBinaryWriter& writer, porter::octomap_t& out) {
  out.utime = last.utime_end;
  out.frame_id = frame_id;
  out.map_id = map_id;
  out.resolution_m = map.resolution_m();
  out.binary = true;
  out.tree_type = "OcTree";
  out.robot_x_m = last.robot.base.x_m;
  out.robot_y_m = last.robot.base.y_m;
  out.robot_yaw_rad = last.robot.base.yaw_rad;
  writer.write(map, out.data);
  out.num_bytes = static_cast<std::int32_t>(out.data.size());
}

}  // namespace porter::mapping::app
