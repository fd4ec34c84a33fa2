// The driver logic against the firmware model, over the in-memory bus and over the LCM-carried
// bus (each test its own udpm port): enable sequence, command streaming and clamping, stale-
// command hold, re-enable after a power cycle, fault decoding, clean shutdown, e-stop.
#include <gtest/gtest.h>

#include <cmath>

#include "arm_rig.hpp"
#include "porter/piper/commands.hpp"
#include "porter/piper/faults.hpp"
#include "porter/piper/feedback.hpp"

namespace porter::piper::test {
namespace {

using can::CanFrame;

class ArmDriverOverBus : public ::testing::TestWithParam<std::string> {
 protected:
  std::string spec(int id) const {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    return bus_spec(GetParam(), std::string(info->name()) + "_" + std::to_string(id));
  }
};

ArmCommand command_to(const JointArray& q, double speed_pct = 100.0) {
  ArmCommand c;
  c.q_rad = q;
  c.speed_pct = speed_pct;
  return c;
}

bool active(const ArmRig& rig) { return rig.driver.phase() == ArmPhase::active; }

double quantized(double q) { return mdeg_to_rad(rad_to_mdeg(q)); }

TEST_P(ArmDriverOverBus, EnableSequenceEnablesThenSetsCanModeThenStreams) {
  ArmRig rig(spec(7761));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0)) << to_string(rig.driver.phase());
  ASSERT_TRUE(rig.ok());
  // Enable first (motor 7 = every joint, 0x02 = enable), then the mode frame, then targets.
  ASSERT_FALSE(rig.driver_frames.empty());
  EXPECT_EQ(rig.driver_frames.front().second, encode_enable({kMotorAllJoints, true}));
  double t_enable = -1, t_mode = -1, t_target = -1;
  for (const auto& [ts, f] : rig.driver_frames) {
    if (f.id == id::kMotorEnable && t_enable < 0) t_enable = ts;
    if (f.id == id::kMotionCtrl2 && t_mode < 0) t_mode = ts;
    if (f.id == id::kJointCtrl12 && t_target < 0) t_target = ts;
  }
  EXPECT_LT(t_enable, t_mode);
  EXPECT_LT(t_mode, t_target);
  ModeCommand m;
  ASSERT_EQ(decode_mode(rig.sent(id::kMotionCtrl2).front(), m), DecodeStatus::ok);
  EXPECT_EQ(m.ctrl_mode, ctrl_mode::kCan);
  EXPECT_EQ(m.move_mode, move_mode::kMoveJ);
  EXPECT_EQ(m.speed_pct, 50);  // the default until a command says otherwise
  EXPECT_TRUE(rig.fw.truth().joint_enabled[0] && rig.fw.truth().joint_enabled[5]);
  EXPECT_EQ(rig.fw.truth().ctrl_mode, ctrl_mode::kCan);
  EXPECT_TRUE(rig.saw_event("no_link -> enabling"));
  EXPECT_TRUE(rig.saw_event("enabling -> setting_mode: every joint reports enabled"));
  EXPECT_TRUE(rig.saw_event("setting_mode -> active"));
  EXPECT_TRUE(rig.saw_event("no ARM_CMD yet: holding"));
  EXPECT_FALSE(rig.saw_event("motor_feedback_stale"));  // the 40 Hz frames follow within 25 ms
  // With no command the driver holds where the arm is and reports no fault.
  rig.run(0.3);
  const ArmDriverStatus s = rig.driver.status(rig.t);
  EXPECT_TRUE(s.holding);
  EXPECT_TRUE(s.enabled);
  EXPECT_TRUE(s.link_ok);
  EXPECT_FALSE(s.fault) << join_names(s.faults);
  EXPECT_EQ(rig.fw.counters().targets_ignored, 0u);
}

TEST_P(ArmDriverOverBus, StreamsCommandsAndClampsThemToTheJointLimits) {
  ArmRig rig(spec(7762));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({0.5, 1.0, -0.8, 0.3, -0.4, 0.6}, 80.0);
  rig.run(1.5);
  for (int j = 0; j < kNumJoints; ++j) {
    EXPECT_DOUBLE_EQ(rig.fw.truth().q_rad[j], quantized(rig.command->q_rad[j])) << "joint " << j + 1;
    EXPECT_NEAR(rig.driver.feedback().q_rad[j], rig.command->q_rad[j], 1e-5);
  }
  EXPECT_EQ(rig.fw.truth().speed_pct, 80);  // speed change sent as a new 0x151
  EXPECT_FALSE(rig.driver.status(rig.t).holding);
  // J4 beyond +1.745 and J2 below 0: clamped by the driver, so the firmware never sees them.
  rig.command = command_to({0.5, -0.3, -0.8, 2.5, -0.4, 0.6});
  rig.run(1.0);
  EXPECT_DOUBLE_EQ(rig.driver.last_targets()[3], 1.745);
  EXPECT_DOUBLE_EQ(rig.driver.last_targets()[1], 0.0);
  EXPECT_DOUBLE_EQ(rig.fw.truth().target_rad[3], quantized(1.745));
  EXPECT_DOUBLE_EQ(rig.fw.truth().q_rad[1], 0.0);
  EXPECT_EQ(rig.fw.truth().limit_bits, 0);
  EXPECT_GT(rig.driver.counters().targets_clamped, 0u);
  EXPECT_TRUE(rig.saw_event("target outside the joint limits, clamped"));
  // Gripper commands follow, clamped to the configured range.
  ArmCommand g = command_to({0.5, 0.5, -0.8, 0.3, -0.4, 0.6});
  g.has_gripper = true;
  g.gripper_m = 0.2;
  g.gripper_effort_nm = 1.0;
  rig.command = g;
  rig.run(2.0);
  EXPECT_TRUE(rig.fw.truth().gripper_enabled);
  EXPECT_DOUBLE_EQ(rig.fw.truth().gripper_m, 0.07);
  EXPECT_NEAR(rig.driver.feedback().gripper_m, 0.07, 1e-9);
  EXPECT_TRUE(rig.saw_event("within the joint limits again"));
}

TEST_P(ArmDriverOverBus, HoldsTheMeasuredPositionWhenCommandsGoStale) {
  ArmRig rig(spec(7763));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({2.0, 0, 0, 0, 0, 0}, 30.0);  // 0.9 rad/s
  rig.run(0.6);
  const double q_when_lost = rig.fw.truth().q_rad[0];
  ASSERT_GT(q_when_lost, 0.2);
  rig.command.reset();  // the tracker stops publishing
  rig.run(0.15);
  EXPECT_FALSE(rig.driver.status(rig.t).cmd_stale);  // not yet: 0.2 s timeout
  rig.run(1.0);
  const ArmDriverStatus s = rig.driver.status(rig.t);
  EXPECT_TRUE(s.cmd_stale);
  EXPECT_TRUE(s.holding);
  EXPECT_EQ(rig.fw.truth().qd_radps[0], 0.0);
  // Stopped close to where it was when the command went stale: 0.2 s more of travel at 0.9
  // rad/s plus braking, far short of the 2.0 rad target.
  EXPECT_LT(rig.fw.truth().q_rad[0], q_when_lost + 0.2 * 0.9 + 0.1);
  EXPECT_TRUE(rig.saw_event("ARM_CMD stale"));
  // Fresh commands move it again.
  rig.command = command_to({0.0, 0, 0, 0, 0, 0});
  rig.run(1.5);
  EXPECT_EQ(rig.fw.truth().q_rad[0], 0.0);
  EXPECT_TRUE(rig.saw_event("ARM_CMD fresh: streaming targets"));
  // enabled = false in the command also holds, without calling it stale.
  ArmCommand off = command_to({1.0, 0, 0, 0, 0, 0});
  off.enabled = false;
  rig.command = off;
  rig.run(0.5);
  EXPECT_EQ(rig.fw.truth().q_rad[0], 0.0);
  EXPECT_TRUE(rig.driver.status(rig.t).holding);
  EXPECT_FALSE(rig.driver.status(rig.t).cmd_stale);
}

TEST_P(ArmDriverOverBus, ReEnablesAfterAPowerCycle) {
  ArmRig rig(spec(7764));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({0.4, 0.2, -0.2, 0, 0, 0});
  rig.run(1.0);
  rig.fw.power_cycle();
  const double t_cycle = rig.t;
  ASSERT_TRUE(rig.run_until([&] { return rig.driver.phase() == ArmPhase::enabling; }, 0.2));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  EXPECT_LT(rig.t - t_cycle, 0.2);
  EXPECT_TRUE(rig.saw_event("arm reports ctrl_mode standby (power cycle or mode change)"));
  EXPECT_GE(rig.sent(id::kMotorEnable, t_cycle).size(), 1u);
  EXPECT_GE(rig.sent(id::kMotionCtrl2, t_cycle).size(), 1u);
  rig.command = command_to({-0.4, 0.5, -0.5, 0, 0, 0});
  rig.run(1.0);
  EXPECT_DOUBLE_EQ(rig.fw.truth().q_rad[0], quantized(-0.4));
  EXPECT_EQ(rig.fw.truth().ctrl_mode, ctrl_mode::kCan);
  // A power-off longer than the link timeout: no_link, then the same recovery.
  rig.fw.set_powered(false);
  rig.run(0.5);
  EXPECT_EQ(rig.driver.phase(), ArmPhase::no_link);
  EXPECT_TRUE(rig.driver.status(rig.t).fault);
  rig.fw.set_powered(true);
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  EXPECT_TRUE(rig.saw_event("link down"));
}

TEST_P(ArmDriverOverBus, DecodesFirmwareFaultsByName) {
  ArmDriverParams wide = rig_driver_params();
  wide.upper_rad[3] = 1.832;  // Agilex's URDF limit for J4, wider than the firmware's 1.745
  ArmRig rig(spec(7765), wide);
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({0, 0, 0, 1.8, 0, 0});
  rig.run(1.0);
  ArmDriverStatus s = rig.driver.status(rig.t);
  EXPECT_EQ(rig.driver.feedback().arm_status, arm_status::kTargetExceedsLimit);
  EXPECT_EQ(rig.driver.feedback().err_code, err_angle_limit_bit(3));
  EXPECT_EQ(join_names(s.faults), "target_exceeds_limit, joint4_angle_limit");
  rig.command = command_to({0, 0, 0, 1.0, 0, 0});
  rig.run(0.2);
  EXPECT_FALSE(rig.driver.status(rig.t).fault);
  EXPECT_TRUE(rig.saw_event("faults cleared"));

  rig.fw.inject_err_code(err_comm_bit(4));
  rig.fw.inject_driver_status(1, 0x02 | 0x80);
  rig.fw.inject_gripper_status(0x20);
  rig.fw.inject_arm_status(arm_status::kCollision);
  rig.run(0.1);
  s = rig.driver.status(rig.t);
  EXPECT_EQ(join_names(s.faults),
            "collision, joint5_comm_error, joint2_motor_over_temperature, joint2_stall_protection, "
            "gripper_driver_error");
  EXPECT_TRUE(rig.saw_event("faults: collision"));
  rig.fw.clear_injected_faults();
  rig.run(0.1);
  EXPECT_FALSE(rig.driver.status(rig.t).fault);

  // A stopped motor stream is a fault; stopped joint angles take the link down.
  rig.fw.set_stream_enabled(FeedbackStream::low_speed, false);
  rig.run(0.5);
  s = rig.driver.status(rig.t);
  EXPECT_EQ(join_names(s.faults), "motor_feedback_stale");
  EXPECT_EQ(rig.driver.phase(), ArmPhase::active);
  rig.fw.set_stream_enabled(FeedbackStream::low_speed, true);
  rig.fw.set_stream_enabled(FeedbackStream::joint_angles, false);
  rig.run(0.3);
  EXPECT_EQ(rig.driver.phase(), ArmPhase::no_link);
  EXPECT_EQ(join_names(rig.driver.status(rig.t).faults), "no_link");
  const std::size_t targets_before = rig.sent(id::kJointCtrl12).size();
  rig.run(0.3);
  EXPECT_EQ(rig.sent(id::kJointCtrl12).size(), targets_before);  // nothing streamed blind
  rig.fw.set_stream_enabled(FeedbackStream::joint_angles, true);
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  EXPECT_FALSE(rig.driver.status(rig.t).fault);
}

TEST_P(ArmDriverOverBus, ShutdownDisablesTheArm) {
  ArmRig rig(spec(7766));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({0.3, 0.3, -0.3, 0, 0, 0});
  rig.run(0.5);
  const double t_stop = rig.t;
  rig.driver.request_shutdown("test", rig.t);
  ASSERT_TRUE(rig.run_until([&] { return rig.driver.finished(); }, 1.0));
  EXPECT_LT(rig.t - t_stop, 0.1);  // confirmed by the next low-speed frames, not the timeout
  const auto disables = rig.sent(id::kMotorEnable, t_stop);
  ASSERT_FALSE(disables.empty());
  EXPECT_EQ(disables.front(), encode_enable({kMotorAll, false}));
  for (int j = 0; j < kNumJoints; ++j) EXPECT_FALSE(rig.fw.truth().joint_enabled[j]);
  EXPECT_TRUE(rig.sent(id::kJointCtrl12, t_stop + 0.001).empty());
  EXPECT_TRUE(rig.saw_event("every joint reports disabled"));
  // Finished means silent.
  const std::size_t n = rig.driver_frames.size();
  rig.run(0.2);
  EXPECT_EQ(rig.driver_frames.size(), n);
}

TEST_P(ArmDriverOverBus, ShutdownWithoutAnArmEndsAtTheTimeout) {
  ArmRig rig(spec(7767));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.fw.set_powered(false);
  const double t_stop = rig.t;
  rig.driver.request_shutdown("test", rig.t);
  ASSERT_TRUE(rig.run_until([&] { return rig.driver.finished(); }, 2.0));
  EXPECT_NEAR(rig.t - t_stop, 0.5, 0.011);
  EXPECT_GE(rig.sent(id::kMotorEnable, t_stop).size(), 5u);  // repeated every 0.1 s
  EXPECT_TRUE(rig.saw_event("disable not confirmed"));
}

TEST_P(ArmDriverOverBus, EmergencyStopHoldsUntilReleasedThenRecovers) {
  ArmRig rig(spec(7768));
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  rig.command = command_to({2.0, 0, 0, 0, 0, 0});
  rig.run(0.3);
  const double t_estop = rig.t;
  rig.driver.on_estop(true, "operator: test", rig.t);
  rig.run(1.0);
  const auto stops = rig.sent(id::kMotionCtrl1, t_estop);
  ASSERT_FALSE(stops.empty());
  EXPECT_EQ(stops.front(), encode_motion({estop_action::kStop, 0, 0}));
  EXPECT_EQ(stops.size(), 1u);  // confirmed at once, not repeated
  EXPECT_TRUE(rig.sent(id::kJointCtrl12, t_estop + 0.001).empty());
  EXPECT_TRUE(rig.fw.truth().estop);
  EXPECT_EQ(rig.fw.truth().qd_radps[0], 0.0);
  const double q_stopped = rig.fw.truth().q_rad[0];
  EXPECT_LT(q_stopped, 1.5);
  ArmDriverStatus s = rig.driver.status(rig.t);
  EXPECT_TRUE(s.estop_active);
  EXPECT_EQ(join_names(s.faults), "emergency_stop");
  // Commands keep coming; nothing moves until the release. A repeated ESTOP changes nothing.
  rig.driver.on_estop(true, "operator: repeat", rig.t);
  rig.run(1.0);
  EXPECT_EQ(rig.fw.truth().q_rad[0], q_stopped);
  // Release: resume, the enable sequence again, then a hold until a command newer than the release.
  rig.command.reset();
  const double t_release = rig.t;
  rig.driver.on_estop(false, "operator: release", rig.t);
  ASSERT_TRUE(rig.run_until([&] { return active(rig); }, 1.0));
  EXPECT_EQ(rig.sent(id::kMotionCtrl1, t_release).front(), encode_motion({estop_action::kResume, 0, 0}));
  EXPECT_FALSE(rig.fw.truth().estop);
  EXPECT_TRUE(rig.saw_event("ESTOP released (operator: release)"));
  EXPECT_TRUE(rig.saw_event("releasing -> enabling: arm left e-stop"));
  rig.run(0.5);
  EXPECT_NEAR(rig.fw.truth().q_rad[0], q_stopped, 1e-5);  // held to the millidegree
  EXPECT_TRUE(rig.driver.status(rig.t).holding);
  rig.command = command_to({0.0, 0, 0, 0, 0, 0});
  rig.run(1.5);
  EXPECT_EQ(rig.fw.truth().q_rad[0], 0.0);
  EXPECT_FALSE(rig.driver.status(rig.t).fault);
}

TEST(ArmDriver, MalformedFramesAreCountedAndLoggedOncePerId) {
  ArmDriver driver(rig_driver_params());
  CanFrame short_angles = encode_joint_angle_pair({0, {1000, 2000}});
  short_angles.dlc = 3;
  driver.on_frame(short_angles, 0.0);
  driver.on_frame(short_angles, 0.001);
  CanFrame long_status = encode_status({});
  long_status.dlc = 12;
  driver.on_frame(long_status, 0.002);
  CanFrame other = encode_status({});
  other.id = 0x3FF;
  driver.on_frame(other, 0.003);
  EXPECT_EQ(driver.counters().frames_received, 4u);
  EXPECT_EQ(driver.counters().frames_malformed, 3u);
  EXPECT_EQ(driver.counters().frames_ignored, 1u);
  EXPECT_EQ(driver.feedback().q_rad[0], 0.0);  // nothing taken from a short frame
  EXPECT_FALSE(driver.feedback().have_status);
  const auto events = driver.take_events();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_NE(events[0].text.find("0x2A5 [3]"), std::string::npos) << events[0].text;
  EXPECT_NE(events[0].text.find("short_frame"), std::string::npos) << events[0].text;
  EXPECT_NE(events[1].text.find("bad_dlc"), std::string::npos) << events[1].text;
}

TEST(ArmDriver, RefusesNonFiniteCommands) {
  ArmDriver driver(rig_driver_params());
  ArmCommand c = command_to({0, 0, 0, 0, 0, 0});
  EXPECT_TRUE(driver.on_command(c, 0.0));
  c.q_rad[3] = std::nan("");
  EXPECT_FALSE(driver.on_command(c, 0.01));
  c.q_rad[3] = 0.0;
  c.has_gripper = true;
  c.gripper_m = INFINITY;
  EXPECT_FALSE(driver.on_command(c, 0.02));
  EXPECT_EQ(driver.counters().commands_accepted, 1u);
}

INSTANTIATE_TEST_SUITE_P(Bus, ArmDriverOverBus, ::testing::Values("memory", "lcm"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace porter::piper::test
