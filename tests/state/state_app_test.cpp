// porter-state's adapter: the strict config and the message conversions.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "porter/core/load_error.hpp"
#include "state_config.hpp"
#include "state_messages.hpp"
#include "hostile_config.hpp"

namespace porter::state_app {
namespace {

const std::string kShipped = std::string(PORTER_SOURCE_DIR) + "/config/state/porter_state.yaml";

std::string shipped_text() {
  std::ifstream in(kShipped);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + "/porter_state_" + name + ".yaml";
  std::ofstream(path) << text;
  return path;
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

void expect_load_error(const std::string& text, const std::string& name,
                       const std::string& expected_key) {
  const std::string path = write_temp(name, text);
  try {
    load_state_config(path);
    ADD_FAILURE() << "no error for " << name;
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected_key), std::string::npos) << e.what();
  }
}

TEST(StateConfig, ShippedConfigLoads) {
  const StateConfig c = load_state_config(kShipped);
  EXPECT_EQ(c.frame_id, "world");
  EXPECT_EQ(c.lio_child_frame_id, "base");
  EXPECT_DOUBLE_EQ(c.rate_hz, 100.0);
  EXPECT_TRUE(c.fusion.use_lio);
  EXPECT_DOUBLE_EQ(c.fusion.base_timeout_s, 0.1);
  EXPECT_DOUBLE_EQ(c.fusion.arm_timeout_s, 0.05);
  EXPECT_DOUBLE_EQ(c.fusion.lio_timeout_s, 0.3);
}

TEST(StateConfig, StrictKeysAndRanges) {
  const std::string text = shipped_text();
  expect_load_error(text + "surprise: 1\n", "unknown", "surprise");
  expect_load_error(replace(text, "  timeout_s: 0.05", "  timeout_s: 0.05\n  extra: 2"),
                    "unknown_nested", "arm.extra");
  expect_load_error(replace(text, "rate_hz: 100", "rate_hz: 5000"), "range", "rate_hz");
  expect_load_error(replace(text, "  timeout_s: 0.1 ", "  timeout_s: -0.1 "), "negative",
                    "base.timeout_s");
  expect_load_error(replace(text, "  use: true", "  use: maybe"), "bool", "lio.use");
  expect_load_error(replace(text, "start_pose: {x_m: 0.0, y_m: 0.0, yaw_rad: 0.0}",
                            "start_pose: {x_m: 0.0, yaw_rad: 0.0}"),
                    "missing", "y_m");
}

TEST(StateMessages, LioYawFromQuaternion) {
  pose_t msg;
  msg.utime = 5;
  msg.frame_id = "world";
  msg.child_frame_id = "base";
  msg.x_m = 1.0;
  msg.y_m = 2.0;
  // Yaw 0.8 about z, then a small roll: the heading is still 0.8.
  const double yaw = 0.8, roll = 0.05;
  msg.qw = std::cos(yaw / 2) * std::cos(roll / 2);
  msg.qx = std::cos(yaw / 2) * std::sin(roll / 2);
  msg.qy = std::sin(yaw / 2) * std::sin(roll / 2);
  msg.qz = std::sin(yaw / 2) * std::cos(roll / 2);
  msg.num_covariance = 0;
  auto c = to_lio(msg, "world", "base");
  ASSERT_TRUE(c.value) << c.error;
  EXPECT_NEAR(c.value->T_W_B.yaw_rad, 0.8, 1e-12);
  EXPECT_EQ(c.value->utime, 5);
  // A non-unit quaternion has the same heading.
  msg.qw *= 2; msg.qx *= 2; msg.qy *= 2; msg.qz *= 2;
  EXPECT_NEAR(to_lio(msg, "world", "base").value->T_W_B.yaw_rad, 0.8, 1e-12);
  msg.child_frame_id = "lidar";
  c = to_lio(msg, "world", "base");
  EXPECT_FALSE(c.value);
  EXPECT_NE(c.error.find("'lidar'"), std::string::npos);
  msg.child_frame_id = "base";
  msg.qw = msg.qx = msg.qy = msg.qz = 0.0;
  EXPECT_FALSE(to_lio(msg, "world", "base").value);
}

TEST(StateMessages, ArmAndOdometryValidation) {
  arm_state_t arm;
  arm.num_joints = 5;
  arm.q_rad.assign(5, 0.0);
  arm.qd_radps.assign(5, 0.0);
  EXPECT_NE(to_arm(arm).error.find("5 joints"), std::string::npos);
  arm.num_joints = 6;
  arm.q_rad.assign(6, 0.1);
  arm.qd_radps.assign(6, 0.0);
  ASSERT_TRUE(to_arm(arm).value);
  arm.q_rad[3] = std::nan("");
  EXPECT_FALSE(to_arm(arm).value);
  base_state_t base{};
  base.odom_x_m = 1.0;
  ASSERT_TRUE(to_odometry(base).value);
  base.v_mps = INFINITY;
  EXPECT_FALSE(to_odometry(base).value);
}

TEST(StateMessages, RobotStateCarriesEverything) {
  state::FusedState f;
  f.utime = 11;
  f.T_W_B = {1.0, 2.0, 3.0};
  f.pose_source = state::PoseSource::lio;
  f.base_valid = true;
  f.pose_valid = true;
  f.base_utime = 7;
  f.pose_utime = 8;
  f.estop_active = true;
  robot_state_t msg = make_robot_state(f, "world");
  EXPECT_EQ(msg.num_joints, 0);
  EXPECT_TRUE(msg.q_rad.empty());
  EXPECT_EQ(msg.pose_source, robot_state_t::POSE_LIO);
  EXPECT_TRUE(msg.estop_active);
  EXPECT_FALSE(msg.arm_valid);
  EXPECT_EQ(msg.pose_utime, 8);
  f.has_arm = true;
  f.q_rad.setConstant(0.25);
  msg = make_robot_state(f, "world");
  ASSERT_EQ(msg.num_joints, 6);
  ASSERT_EQ(msg.q_rad.size(), 6u);
  EXPECT_DOUBLE_EQ(msg.q_rad[5], 0.25);
  // It encodes (counts agree with the arrays).
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  EXPECT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
}

}  // namespace
}  // namespace porter::state_app

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(StateConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("state/porter_state.yaml", [](const std::string& f) { porter::state_app::load_state_config(f); });
  EXPECT_GE(replaced, 11 * 13);
}
