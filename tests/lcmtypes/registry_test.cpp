// The channel registry must cover DESIGN §2 (hard-coded below as the specification), with the
// right types and owners, unique well-formed names and sane rates.

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "porter/channels.hpp"

namespace porter::channels {
namespace {

struct SpecRow {
  std::string name;
  std::string type_name;
  std::string owner;
  double min_rate_hz;  // DESIGN §2 rate range; 0/0 = event-driven or unspecified
  double max_rate_hz;
};

// DESIGN §2, "Processes and channels", plus the e-stop, heartbeat and simulator channels.
const std::vector<SpecRow>& design_channels() {
  static const std::vector<SpecRow> spec = {
      {"LIDAR_POINTS", "point_cloud_t", "porter-lidar", 10.0, 10.0},
      {"LIDAR_IMU", "imu_t", "porter-lidar", 200.0, 200.0},
      {"MAP_OCTOMAP", "octomap_t", "porter-mapper", 2.0, 5.0},
      {"ROBOT_STATE", "robot_state_t", "porter-state", 100.0, 100.0},
      {"PLAN_GOAL", "plan_goal_t", "operator", 0.0, 0.0},
      {"PAYLOAD", "payload_t", "operator", 0.0, 0.0},
      {"TRAJECTORY", "minco_trajectory_t", "porter-planner", 0.0, 0.0},
      {"PLANNER_STATUS", "planner_status_t", "porter-planner", 0.0, 0.0},
      {"BASE_CMD", "base_cmd_t", "porter-tracker", 100.0, 100.0},
      {"ARM_CMD", "arm_cmd_t", "porter-tracker", 100.0, 100.0},
      {"TRACKER_STATUS", "tracker_status_t", "porter-tracker", 1.0, 100.0},
      {"BASE_STATE", "base_state_t", "porter-base", 50.0, 50.0},
      {"ARM_STATE", "arm_state_t", "porter-arm", 200.0, 200.0},
      {"LIO_POSE", "pose_t", "porter-sim", 1.0, 100.0},
      {"CAN_BASE", "can_frame_t", "porter-base, porter-sim", 0.0, 0.0},
      {"CAN_ARM", "can_frame_t", "porter-arm, porter-sim", 0.0, 0.0},
      {"ESTOP", "estop_t", "operator", 0.0, 0.0},
      {"HEARTBEAT", "process_heartbeat_t", "all", 1.0, 1.0},
      {"SIM_TRUTH", "robot_state_t", "porter-sim", 10.0, 1000.0},
      {"SIM_COMMAND", "sim_command_t", "operator", 0.0, 0.0},
  };
  return spec;
}

TEST(ChannelRegistry, CoversDesignTable) {
  for (const SpecRow& row : design_channels()) {
    SCOPED_TRACE(row.name);
    const ChannelInfo* info = find(row.name);
    ASSERT_NE(info, nullptr) << "channel missing from the registry";
    EXPECT_EQ(info->name, row.name);
    EXPECT_EQ(info->type_name, row.type_name);
    EXPECT_EQ(info->owner, row.owner);
    EXPECT_GE(info->rate_hz, row.min_rate_hz);
    EXPECT_LE(info->rate_hz, row.max_rate_hz);
  }
  EXPECT_EQ(kAll.size(), design_channels().size()) << "registry has channels the spec lacks";
}

TEST(ChannelRegistry, NamesAreUniqueAndLiteralSafe) {
  std::set<std::string_view> names;
  for (const ChannelInfo& info : kAll) {
    SCOPED_TRACE(std::string(info.name));
    EXPECT_TRUE(names.insert(info.name).second) << "duplicate channel name";
    ASSERT_FALSE(info.name.empty());
    EXPECT_LE(info.name.size(), 63u) << "LCM limits channel names to 63 characters";
    // LCM subscribes by regular expression; [A-Z0-9_] names match only themselves.
    for (char c : info.name) {
      EXPECT_TRUE((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_') << c;
    }
  }
}

TEST(ChannelRegistry, RowsAreComplete) {
  for (const ChannelInfo& info : kAll) {
    SCOPED_TRACE(std::string(info.name));
    EXPECT_TRUE(std::isfinite(info.rate_hz));
    EXPECT_GE(info.rate_hz, 0.0);
    EXPECT_FALSE(info.type_name.empty());
    EXPECT_FALSE(info.owner.empty());
    EXPECT_FALSE(info.description.empty());
  }
}

TEST(ChannelRegistry, FindReturnsNullForUnknownNames) {
  EXPECT_EQ(find("NO_SUCH_CHANNEL"), nullptr);
  EXPECT_EQ(find(""), nullptr);
  EXPECT_EQ(find("robot_state"), nullptr) << "lookup is case-sensitive";
  static_assert(find("ROBOT_STATE") == &kAll[8], "find is usable at compile time");
}

// The typed descriptor's C++ type must be the type the row names, and its row must be in kAll.
template <class T>
void expect_typed_row(const Channel<T>& channel) {
  SCOPED_TRACE(std::string(channel.name()));
  EXPECT_EQ(channel.info.type_name, T::getTypeName());
  const ChannelInfo* row = find(channel.name());
  ASSERT_NE(row, nullptr) << "typed channel missing from kAll";
  EXPECT_EQ(row->type_name, channel.info.type_name);
  EXPECT_EQ(row->owner, channel.info.owner);
  EXPECT_EQ(row->rate_hz, channel.info.rate_hz);
  EXPECT_EQ(row->description, channel.info.description);
}

TEST(ChannelRegistry, TypedDescriptorsMatchTheirRows) {
  expect_typed_row(kLidarPoints);
  expect_typed_row(kLidarImu);
  expect_typed_row(kLioPose);
  expect_typed_row(kMapOctomap);
  expect_typed_row(kPlanGoal);
  expect_typed_row(kPayload);
  expect_typed_row(kTrajectory);
  expect_typed_row(kPlannerStatus);
  expect_typed_row(kRobotState);
  expect_typed_row(kBaseCmd);
  expect_typed_row(kArmCmd);
  expect_typed_row(kTrackerStatus);
  expect_typed_row(kBaseState);
  expect_typed_row(kArmState);
  expect_typed_row(kCanBase);
  expect_typed_row(kCanArm);
  expect_typed_row(kEstop);
  expect_typed_row(kHeartbeat);
  expect_typed_row(kSimTruth);
  expect_typed_row(kSimCommand);
}

TEST(ChannelRegistry, EveryMessageTypeTravelsOnSomeChannel) {
  std::set<std::string_view> carried;
  for (const ChannelInfo& info : kAll) carried.insert(info.type_name);
  std::stringstream types(PORTER_LCM_TYPE_NAMES);  // from lcmtypes/CMakeLists.txt
  std::string type;
  int count = 0;
  while (std::getline(types, type, ',')) {
    ++count;
    EXPECT_TRUE(carried.count(type) == 1) << type << " is generated but no channel carries it";
  }
  EXPECT_GE(count, 17);
}

}  // namespace
}  // namespace porter::channels
