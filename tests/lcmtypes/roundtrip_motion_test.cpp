// Round trips of the base/arm command and state types: every field must survive encode/decode.

#include <gtest/gtest.h>

#include "porter/arm_cmd_t.hpp"
#include "porter/arm_state_t.hpp"
#include "porter/base_cmd_t.hpp"
#include "porter/base_state_t.hpp"
#include "porter/pose_t.hpp"
#include "porter/robot_state_t.hpp"
#include "porter/tracker_status_t.hpp"
#include "roundtrip_support.hpp"

namespace porter {
namespace {

using test::expect_rejects;
using test::roundtrip;

TEST(LcmRoundTrip, BaseCmd) {
  base_cmd_t m{};
  m.utime = 1'700'000'000'123'456;
  m.enabled = true;
  m.v_mps = -0.4375;
  m.omega_radps = 1.25e-3;
  m.plan_id = 42;
  m.source = "porter-tracker";
  const base_cmd_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.enabled, m.enabled);
  EXPECT_EQ(r.v_mps, m.v_mps);
  EXPECT_EQ(r.omega_radps, m.omega_radps);
  EXPECT_EQ(r.plan_id, m.plan_id);
  EXPECT_EQ(r.source, m.source);
  expect_rejects(m, pose_t{});
}

TEST(LcmRoundTrip, BaseState) {
  base_state_t m{};
  m.utime = 123'456'789;
  m.v_mps = 0.812;
  m.omega_radps = -0.33;
  m.wheel_left_m = 1234.5678;
  m.wheel_right_m = 1230.0001;
  m.odom_x_m = 12.5;
  m.odom_y_m = -3.75;
  m.odom_yaw_rad = 2.9;
  m.num_motors = 4;
  m.motor_speed_rpm = {101.0, -102.5, 103.0, -104.25};
  m.motor_current_a = {1.1, 2.2, 3.3, 4.4};
  m.driver_temperature_c = {31.0, 32.0, 33.5, 34.0};
  m.battery_voltage_v = 25.3;
  m.battery_soc_pct = 87.5;
  m.vehicle_state = base_state_t::VEHICLE_EXCEPTION;
  m.control_mode = base_state_t::MODE_CAN;
  m.fault_bits = 0x0205;
  m.cmd_stale = true;
  m.estop_active = false;
  m.link_ok = true;
  const base_state_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.v_mps, m.v_mps);
  EXPECT_EQ(r.omega_radps, m.omega_radps);
  EXPECT_EQ(r.wheel_left_m, m.wheel_left_m);
  EXPECT_EQ(r.wheel_right_m, m.wheel_right_m);
  EXPECT_EQ(r.odom_x_m, m.odom_x_m);
  EXPECT_EQ(r.odom_y_m, m.odom_y_m);
  EXPECT_EQ(r.odom_yaw_rad, m.odom_yaw_rad);
  EXPECT_EQ(r.num_motors, m.num_motors);
  EXPECT_EQ(r.motor_speed_rpm, m.motor_speed_rpm);
  EXPECT_EQ(r.motor_current_a, m.motor_current_a);
  EXPECT_EQ(r.driver_temperature_c, m.driver_temperature_c);
  EXPECT_EQ(r.battery_voltage_v, m.battery_voltage_v);
  EXPECT_EQ(r.battery_soc_pct, m.battery_soc_pct);
  EXPECT_EQ(r.vehicle_state, m.vehicle_state);
  EXPECT_EQ(r.control_mode, m.control_mode);
  EXPECT_EQ(r.fault_bits, m.fault_bits);
  EXPECT_EQ(r.cmd_stale, m.cmd_stale);
  EXPECT_EQ(r.estop_active, m.estop_active);
  EXPECT_EQ(r.link_ok, m.link_ok);
  expect_rejects(m, base_cmd_t{});
}

TEST(LcmRoundTrip, ArmCmd) {
  arm_cmd_t m{};
  m.utime = 987'654'321;
  m.enabled = true;
  m.num_joints = 6;
  m.q_rad = {0.1, 1.2, -1.3, 0.4, -0.5, 2.0};
  m.qd_radps = {-0.01, 0.02, -0.03, 0.04, -0.05, 0.06};
  m.speed_pct = 35.0;
  m.has_gripper = true;
  m.gripper_m = 0.0425;
  m.gripper_effort_nm = 1.5;
  m.plan_id = 7;
  m.source = "porter-tracker";
  const arm_cmd_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.enabled, m.enabled);
  EXPECT_EQ(r.num_joints, m.num_joints);
  EXPECT_EQ(r.q_rad, m.q_rad);
  EXPECT_EQ(r.qd_radps, m.qd_radps);
  EXPECT_EQ(r.speed_pct, m.speed_pct);
  EXPECT_EQ(r.has_gripper, m.has_gripper);
  EXPECT_EQ(r.gripper_m, m.gripper_m);
  EXPECT_EQ(r.gripper_effort_nm, m.gripper_effort_nm);
  EXPECT_EQ(r.plan_id, m.plan_id);
  EXPECT_EQ(r.source, m.source);
  expect_rejects(m, base_cmd_t{});
}

TEST(LcmRoundTrip, ArmState) {
  arm_state_t m{};
  m.utime = 55'000'001;
  m.num_joints = 6;
  m.q_rad = {0.5, 1.5, -2.5, 0.25, -0.75, 1.75};
  m.qd_radps = {0.11, -0.12, 0.13, -0.14, 0.15, -0.16};
  m.effort_nm = {3.1, -4.1, 5.9, -2.6, 0.5, -0.35};
  m.motor_temperature_c = {40.0, 41.0, 42.0, 43.0, 44.0, 45.5};
  m.joint_status_bits = {0, 0x40, 0x41, 0x02, 0x80, 0x7f};
  m.joint_enabled = {1, 1, 0, 1, 0, 1};
  m.gripper_m = 0.031;
  m.gripper_effort_nm = 0.8;
  m.ctrl_mode = arm_state_t::CTRL_CAN;
  m.arm_status = 0x07;
  m.err_code = 0x0302;
  m.enabled = false;
  m.fault = true;
  m.cmd_stale = true;
  m.estop_active = true;
  m.link_ok = false;
  const arm_state_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.num_joints, m.num_joints);
  EXPECT_EQ(r.q_rad, m.q_rad);
  EXPECT_EQ(r.qd_radps, m.qd_radps);
  EXPECT_EQ(r.effort_nm, m.effort_nm);
  EXPECT_EQ(r.motor_temperature_c, m.motor_temperature_c);
  EXPECT_EQ(r.joint_status_bits, m.joint_status_bits);
  EXPECT_EQ(r.joint_enabled, m.joint_enabled);
  EXPECT_EQ(r.gripper_m, m.gripper_m);
  EXPECT_EQ(r.gripper_effort_nm, m.gripper_effort_nm);
  EXPECT_EQ(r.ctrl_mode, m.ctrl_mode);
  EXPECT_EQ(r.arm_status, m.arm_status);
  EXPECT_EQ(r.err_code, m.err_code);
  EXPECT_EQ(r.enabled, m.enabled);
  EXPECT_EQ(r.fault, m.fault);
  EXPECT_EQ(r.cmd_stale, m.cmd_stale);
  EXPECT_EQ(r.estop_active, m.estop_active);
  EXPECT_EQ(r.link_ok, m.link_ok);
  expect_rejects(m, arm_cmd_t{});
}

TEST(LcmRoundTrip, RobotState) {
  robot_state_t m{};
  m.utime = 1'000'000'000'000'001;
  m.frame_id = "world";
  m.x_m = 3.25;
  m.y_m = -7.5;
  m.yaw_rad = -3.0;
  m.v_mps = 0.6;
  m.omega_radps = 0.2;
  m.num_joints = 6;
  m.q_rad = {0.0, 1.0, -1.0, 0.5, -0.5, 3.0};
  m.qd_radps = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6};
  m.pose_source = robot_state_t::POSE_LIO;
  m.base_valid = true;
  m.arm_valid = false;
  m.pose_valid = true;
  m.base_utime = 999'999'999'990'000;
  m.arm_utime = 999'999'999'980'000;
  m.pose_utime = 999'999'999'970'000;
  m.estop_active = true;
  const robot_state_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.x_m, m.x_m);
  EXPECT_EQ(r.y_m, m.y_m);
  EXPECT_EQ(r.yaw_rad, m.yaw_rad);
  EXPECT_EQ(r.v_mps, m.v_mps);
  EXPECT_EQ(r.omega_radps, m.omega_radps);
  EXPECT_EQ(r.num_joints, m.num_joints);
  EXPECT_EQ(r.q_rad, m.q_rad);
  EXPECT_EQ(r.qd_radps, m.qd_radps);
  EXPECT_EQ(r.pose_source, m.pose_source);
  EXPECT_EQ(r.base_valid, m.base_valid);
  EXPECT_EQ(r.arm_valid, m.arm_valid);
  EXPECT_EQ(r.pose_valid, m.pose_valid);
  EXPECT_EQ(r.base_utime, m.base_utime);
  EXPECT_EQ(r.arm_utime, m.arm_utime);
  EXPECT_EQ(r.pose_utime, m.pose_utime);
  EXPECT_EQ(r.estop_active, m.estop_active);
  expect_rejects(m, base_state_t{});
}

TEST(LcmRoundTrip, Pose) {
  pose_t m{};
  m.utime = 77'000'000;
  m.frame_id = "world";
  m.child_frame_id = "base";
  m.x_m = 1.5;
  m.y_m = -2.5;
  m.z_m = 0.125;
  m.qw = 0.9238795325112867;
  m.qx = 0.0;
  m.qy = 0.0;
  m.qz = 0.3826834323650898;
  m.num_covariance = 36;
  m.covariance.resize(36);
  for (int i = 0; i < 36; ++i) m.covariance[i] = 1e-4 * (i + 1) * ((i % 7 == 0) ? 10.0 : 1.0);
  const pose_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.child_frame_id, m.child_frame_id);
  EXPECT_EQ(r.x_m, m.x_m);
  EXPECT_EQ(r.y_m, m.y_m);
  EXPECT_EQ(r.z_m, m.z_m);
  EXPECT_EQ(r.qw, m.qw);
  EXPECT_EQ(r.qx, m.qx);
  EXPECT_EQ(r.qy, m.qy);
  EXPECT_EQ(r.qz, m.qz);
  EXPECT_EQ(r.num_covariance, m.num_covariance);
  EXPECT_EQ(r.covariance, m.covariance);
  expect_rejects(m, robot_state_t{});
}

TEST(LcmRoundTrip, PoseWithoutCovariance) {
  pose_t m{};
  m.utime = 5;
  m.frame_id = "odom";
  m.child_frame_id = "lidar";
  m.qw = 1.0;
  m.num_covariance = 0;
  const pose_t r = roundtrip(m);
  EXPECT_EQ(r.num_covariance, 0);
  EXPECT_TRUE(r.covariance.empty());
  EXPECT_EQ(r.child_frame_id, "lidar");
}

TEST(LcmRoundTrip, TrackerStatus) {
  tracker_status_t m{};
  m.utime = 31'415'926;
  m.plan_id = 12;
  m.state = tracker_status_t::STATE_STALE_STATE;
  m.t_s = 4.75;
  m.duration_s = 12.5;
  m.along_track_error_m = 0.031;
  m.cross_track_error_m = -0.012;
  m.yaw_error_rad = 0.05;
  m.num_joints = 6;
  m.q_error_rad = {0.001, -0.002, 0.003, -0.004, 0.005, -0.006};
  m.loop_period_s = 0.0101;
  m.max_loop_jitter_s = 0.0004;
  m.loop_overruns = 3;
  m.message = "robot state older than 100 ms";
  const tracker_status_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.plan_id, m.plan_id);
  EXPECT_EQ(r.state, m.state);
  EXPECT_EQ(r.t_s, m.t_s);
  EXPECT_EQ(r.duration_s, m.duration_s);
  EXPECT_EQ(r.along_track_error_m, m.along_track_error_m);
  EXPECT_EQ(r.cross_track_error_m, m.cross_track_error_m);
  EXPECT_EQ(r.yaw_error_rad, m.yaw_error_rad);
  EXPECT_EQ(r.num_joints, m.num_joints);
  EXPECT_EQ(r.q_error_rad, m.q_error_rad);
  EXPECT_EQ(r.loop_period_s, m.loop_period_s);
  EXPECT_EQ(r.max_loop_jitter_s, m.max_loop_jitter_s);
  EXPECT_EQ(r.loop_overruns, m.loop_overruns);
  EXPECT_EQ(r.message, m.message);
  expect_rejects(m, arm_state_t{});
}

}  // namespace
}  // namespace porter
