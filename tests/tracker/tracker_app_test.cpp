// porter-tracker's adapter: the strict config (with the robot's limits) and the message
// conversions (ROBOT_STATE and TRAJECTORY in, BASE_CMD / ARM_CMD / TRACKER_STATUS out).

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "porter/core/load_error.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "tracker_config.hpp"
#include "tracker_messages.hpp"
#include "trajectory_fixtures.hpp"
#include "hostile_config.hpp"

namespace porter::tracker_app {
namespace {

const std::string kShipped = std::string(PORTER_SOURCE_DIR) + "/config/tracker/porter_tracker.yaml";

std::string shipped_text() {
  std::ifstream in(kShipped);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  // The robot path is relative to the shipped file; make it absolute for copies elsewhere.
  const std::string rel = "robot: ../robots/";
  text.replace(text.find(rel), rel.size(),
               "robot: " + std::string(PORTER_SOURCE_DIR) + "/config/robots/");
  return text;
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

void expect_load_error(const std::string& text, const std::string& name,
                       const std::string& expected) {
  const std::string path = testing::TempDir() + "/porter_tracker_" + name + ".yaml";
  std::ofstream(path) << text;
  try {
    load_tracker_config(path);
    ADD_FAILURE() << "no error for " << name;
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(TrackerConfig, ShippedConfigLoadsWithRobotLimits) {
  const TrackerConfig c = load_tracker_config(kShipped);
  EXPECT_DOUBLE_EQ(c.rate_hz, 100.0);
  EXPECT_DOUBLE_EQ(c.params.period_s, 0.01);
  EXPECT_DOUBLE_EQ(c.params.base_limits.wheel_radius_m, 0.0875);
  EXPECT_DOUBLE_EQ(c.params.base_limits.wheel_omega_max_radps, 12.0);
  EXPECT_TRUE((c.params.joint_velocity_max_radps.array() > 0.0).all());
  EXPECT_EQ(c.params.frame_id, "world");
  EXPECT_DOUBLE_EQ(c.params.gains.k_y_1pm2, 4.0);
  EXPECT_DOUBLE_EQ(c.params.trajectory_timeout_s, 0.0);
}

TEST(TrackerConfig, StrictKeysAndRanges) {
  const std::string text = shipped_text();
  expect_load_error(text + "bonus: 1\n", "unknown", "bonus");
  expect_load_error(replace(text, "  k_x_1ps: 1.5", "  kx: 1.5"), "renamed", "gains.kx");
  expect_load_error(replace(text, "  k_y_1pm2: 4.0", "  k_y_1pm2: 0"), "zero_gain", "gains.k_y_1pm2");
  expect_load_error(replace(text, "  sched_priority: 80", "  sched_priority: 120"), "priority",
                    "loop.sched_priority");
  expect_load_error(replace(text, "  status_rate_hz: 10", "  status_rate_hz: 200"), "status",
                    "loop.status_rate_hz");
  expect_load_error(replace(text, "  state_timeout_s: 0.1", "  state_timeout_s: 0.001"),
                    "timeout", "watchdog.state_timeout_s");
  expect_load_error(replace(text, "  speed_pct: 100", "  speed_pct: 150"), "speed", "arm.speed_pct");
  expect_load_error(replace(text, "robot: ", "robot: /nonexistent"), "robot", "nonexistent");
}

TEST(TrackerMessages, TrajectoryRoundTripAndDimensionCheck) {
  const Trajectory traj = test::straight(0.4, 1.0, -1);
  minco_trajectory_t msg = to_msg(traj, 123, 7, "world", "t_bar");
  msg.utime = 100;
  TrajectoryConversion c = to_offer(msg);
  ASSERT_TRUE(c.offer) << c.error;
  EXPECT_EQ(c.offer->start_utime, 123);
  EXPECT_EQ(c.offer->utime, 100);
  EXPECT_EQ(c.offer->plan_id, 7);
  EXPECT_EQ(c.offer->frame_id, "world");
  EXPECT_DOUBLE_EQ(c.offer->trajectory.total_duration_s(), traj.total_duration_s());
  EXPECT_EQ(c.offer->trajectory.piece(0).eta, -1);
  msg.dimension = 7;
  c = to_offer(msg);
  EXPECT_FALSE(c.offer);
  EXPECT_NE(c.error.find("dimension 7, expected 8"), std::string::npos) << c.error;
  msg.dimension = 8;
  msg.coeffs[3] = std::nan("");
  EXPECT_FALSE(to_offer(msg).offer);
}

TEST(TrackerMessages, RobotStateValidation) {
  robot_state_t msg{};
  msg.frame_id = "world";
  msg.num_joints = 6;
  msg.q_rad.assign(6, 0.1);
  msg.qd_radps.assign(6, 0.0);
  msg.pose_valid = msg.base_valid = msg.arm_valid = true;
  msg.x_m = 1.5;
  StateConversion c = to_measured_state(msg, "world");
  ASSERT_TRUE(c.state) << c.error;
  EXPECT_DOUBLE_EQ(c.state->pose.x_m, 1.5);
  EXPECT_DOUBLE_EQ(c.state->q_rad[5], 0.1);
  EXPECT_FALSE(to_measured_state(msg, "odom").state);
  msg.q_rad.pop_back();
  EXPECT_FALSE(to_measured_state(msg, "world").state);
  msg.q_rad.push_back(0.1);
  msg.yaw_rad = NAN;
  EXPECT_FALSE(to_measured_state(msg, "world").state);
}

TEST(TrackerMessages, CommandsAndStatus) {
  tracker::TrackerOutput out;
  out.state = tracker::TrackerState::tracking;
  out.base_enabled = true;
  out.base = {0.3, -0.1};
  out.arm_enabled = true;
  out.q_rad.setConstant(0.2);
  out.qd_radps.setConstant(0.05);
  out.plan_id = 4;
  out.error_reference_frame = {0.01, -0.02, 0.03};
  const base_cmd_t b = make_base_cmd(out, 99);
  EXPECT_TRUE(b.enabled);
  EXPECT_DOUBLE_EQ(b.v_mps, 0.3);
  EXPECT_EQ(b.plan_id, 4);
  EXPECT_EQ(b.source, "porter-tracker");
  const arm_cmd_t a = make_arm_cmd(out, 80.0, 99);
  ASSERT_EQ(a.num_joints, 6);
  EXPECT_DOUBLE_EQ(a.qd_radps[2], 0.05);
  EXPECT_DOUBLE_EQ(a.speed_pct, 80.0);
  const tracker_status_t s = make_status(out, "plan 3 refused: x", {0.0101, 0.0003, 2}, 99);
  EXPECT_EQ(s.state, tracker_status_t::STATE_TRACKING);
  EXPECT_DOUBLE_EQ(s.cross_track_error_m, -0.02);
  EXPECT_EQ(s.message, "plan 3 refused: x");
  EXPECT_EQ(s.loop_overruns, 2);
  // Disabled output: zero velocities whatever the fields hold.
  out.base_enabled = out.arm_enabled = false;
  out.state = tracker::TrackerState::estop;
  out.message = "ESTOP: operator";
  EXPECT_EQ(make_base_cmd(out, 1).v_mps, 0.0);
  EXPECT_EQ(make_arm_cmd(out, 80.0, 1).qd_radps[0], 0.0);
  EXPECT_EQ(make_status(out, "", {}, 1).message, "ESTOP: operator");
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(a.getEncodedSize()));
  EXPECT_EQ(a.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
}

}  // namespace
}  // namespace porter::tracker_app

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(TrackerConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("tracker/porter_tracker.yaml", [](const std::string& f) { porter::tracker_app::load_tracker_config(f); });
  EXPECT_GE(replaced, 11 * 15);
}
