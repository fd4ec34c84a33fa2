// PiperFirmware on its own, driven in simulated time: power-up state, gating of targets, motion
// within the speed limit, feedback rates, joint-limit flags, e-stop, disable, gripper, power
// cycle, fault hooks, and the flange pose of the DH model.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "porter/piper/commands.hpp"
#include "porter/piper/feedback.hpp"
#include "porter/piper/piper_dh.hpp"
#include "porter/piper/piper_firmware.hpp"

namespace porter::piper {
namespace {

using can::CanFrame;
constexpr double kPi = 3.14159265358979323846;

struct Harness {
  explicit Harness(const PiperFirmwareParams& p = {}) : fw(p) {}
  /// Advances by `duration_s` in steps of `step_s`, keeping every frame sent.
  void run(double duration_s, double step_s = 0.001) {
    const double end = t + duration_s;
    while (t < end - 1e-12) {
      t = std::min(end, t + step_s);
      fw.advance(t, out);
    }
  }
  void send(const CanFrame& f) { fw.receive(f, t); }
  void enable_and_can_mode(std::uint8_t speed = 50) {
    send(encode_enable({kMotorAllJoints, true}));
    ModeCommand m;
    m.speed_pct = speed;
    send(encode_mode(m));
    run(0.05);
  }
  void targets(const std::array<double, kNumJoints>& q) {
    for (const CanFrame& f : encode_joint_targets(q)) send(f);
  }
  /// The newest decoded 0x2A1 in `out`.
  StatusFeedback status() const {
    StatusFeedback s;
    for (auto it = out.rbegin(); it != out.rend(); ++it) {
      if (decode_status(*it, s) == DecodeStatus::ok) return s;
    }
    ADD_FAILURE() << "no status frame";
    return s;
  }
  LowSpeedFeedback low_speed(int joint) const {
    LowSpeedFeedback l;
    for (auto it = out.rbegin(); it != out.rend(); ++it) {
      if (decode_low_speed(*it, l) == DecodeStatus::ok && l.joint == joint) return l;
    }
    ADD_FAILURE() << "no low-speed frame for joint " << joint;
    return l;
  }
  PiperFirmware fw;
  double t = 0.0;
  std::vector<CanFrame> out;
};

TEST(PiperFirmware, PowersUpDisabledInStandbyAndIgnoresTargetsUntilEnabledAndInCanMode) {
  Harness h;
  h.run(0.05);
  EXPECT_EQ(h.status().ctrl_mode, ctrl_mode::kStandby);
  EXPECT_FALSE(h.low_speed(0).enabled());
  h.targets({0.5, 0.5, -0.5, 0, 0, 0});
  EXPECT_EQ(h.fw.counters().targets_ignored, 3u);
  h.send(encode_enable({kMotorAllJoints, true}));
  h.run(0.05);
  EXPECT_TRUE(h.fw.truth().joint_enabled[5]);
  EXPECT_TRUE(h.low_speed(5).enabled());
  h.targets({0.5, 0.5, -0.5, 0, 0, 0});  // enabled but still standby
  EXPECT_EQ(h.fw.counters().targets_ignored, 6u);
  h.run(0.2);
  EXPECT_EQ(h.fw.truth().q_rad[0], 0.0);
  ModeCommand m;
  m.move_mode = move_mode::kMoveP;  // CAN mode but not MOVE J
  h.send(encode_mode(m));
  h.targets({0.5, 0.5, -0.5, 0, 0, 0});
  EXPECT_EQ(h.fw.counters().targets_ignored, 9u);
  h.send(encode_mode(ModeCommand{}));
  h.targets({0.5, 0.5, -0.5, 0, 0, 0});
  EXPECT_EQ(h.fw.counters().targets_ignored, 9u);
  h.run(1.0);
  // Targets travel in millidegrees.
  EXPECT_DOUBLE_EQ(h.fw.truth().q_rad[0], mdeg_to_rad(rad_to_mdeg(0.5)));
  EXPECT_DOUBLE_EQ(h.fw.truth().q_rad[2], mdeg_to_rad(rad_to_mdeg(-0.5)));
  EXPECT_EQ(h.status().ctrl_mode, ctrl_mode::kCan);
  EXPECT_EQ(h.status().move_mode, move_mode::kMoveJ);
}

TEST(PiperFirmware, SendsEveryFeedbackFrameAtItsRateWhateverTheCallRate) {
  Harness fine, coarse;
  fine.run(1.0, 0.001);
  coarse.run(1.0, 0.02);
  std::map<std::uint32_t, int> count;
  for (const CanFrame& f : fine.out) ++count[f.id];
  for (std::uint32_t id = 0x2A1; id <= 0x2A8; ++id) EXPECT_EQ(count[id], 200) << std::hex << id;
  for (std::uint32_t id = 0x251; id <= 0x256; ++id) EXPECT_EQ(count[id], 200) << std::hex << id;
  for (std::uint32_t id = 0x261; id <= 0x266; ++id) EXPECT_EQ(count[id], 40) << std::hex << id;
  EXPECT_EQ(fine.out.size(), 3040u);  // the arm's published 3040 frames/s
  ASSERT_EQ(fine.out.size(), coarse.out.size());
  for (std::size_t i = 0; i < fine.out.size(); ++i) {
    EXPECT_EQ(fine.out[i], coarse.out[i]);
    EXPECT_EQ(fine.out[i].utime, coarse.out[i].utime);
    EXPECT_EQ(fine.out[i].dlc, 8);
  }
  EXPECT_EQ(fine.out.front().utime, 5000);   // first frames at 5 ms
  EXPECT_EQ(fine.out.back().utime, 1000000);
}

TEST(PiperFirmware, MovesWithinTheSpeedLimitAndStopsAtTheTarget) {
  for (std::uint8_t speed : {std::uint8_t{50}, std::uint8_t{100}}) {
    Harness h;
    h.enable_and_can_mode(speed);
    const double v_max = 3.0 * speed / 100.0;
    h.targets({1.0, 0.4, -1.0, 0.2, -0.3, 1.5});
    double max_speed = 0.0;
    std::array<double, kNumJoints> prev = h.fw.truth().q_rad;
    for (int i = 0; i < 1500; ++i) {
      h.run(0.001);
      for (int j = 0; j < kNumJoints; ++j) {
        max_speed = std::max(max_speed, std::abs(h.fw.truth().q_rad[j] - prev[j]) / 0.001);
        EXPECT_LE(std::abs(h.fw.truth().qd_radps[j]), v_max + 1e-9);
      }
      prev = h.fw.truth().q_rad;
    }
    EXPECT_LE(max_speed, v_max + 1e-9);
    EXPECT_GT(max_speed, 0.99 * v_max);  // it does reach the limit on the long moves
    const auto& q = h.fw.truth().q_rad;
    EXPECT_DOUBLE_EQ(q[0], mdeg_to_rad(rad_to_mdeg(1.0)));
    EXPECT_DOUBLE_EQ(q[5], mdeg_to_rad(rad_to_mdeg(1.5)));
    for (double v : h.fw.truth().qd_radps) EXPECT_EQ(v, 0.0);
    EXPECT_EQ(h.status().motion_status, 0);
    // The feedback reports the truth to the millidegree.
    JointAnglePair p;
    for (auto it = h.out.rbegin(); it != h.out.rend(); ++it) {
      if (decode_joint_angle_pair(*it, p) == DecodeStatus::ok && p.first == 0) break;
    }
    EXPECT_EQ(p.mdeg[0], rad_to_mdeg(q[0]));
    EXPECT_EQ(p.mdeg[1], rad_to_mdeg(q[1]));
  }
}

TEST(PiperFirmware, OutOfRangeTargetRaisesTheJointLimitErrorAndIsClamped) {
  Harness h;
  h.enable_and_can_mode(100);
  h.targets({0, 0, 0, 2.0, 0, 0});  // J4 limit 1.745
  h.run(1.5);
  EXPECT_NEAR(h.fw.truth().q_rad[3], 1.745, 1e-12);
  StatusFeedback s = h.status();
  EXPECT_EQ(s.err_code, err_angle_limit_bit(3));
  EXPECT_EQ(s.err_code >> 8, 0x08);  // B6 bit 3
  EXPECT_EQ(s.arm_status, arm_status::kTargetExceedsLimit);
  h.targets({0, 0, 0, 1.0, 0, 0});
  h.run(0.05);
  s = h.status();
  EXPECT_EQ(s.err_code, 0);
  EXPECT_EQ(s.arm_status, arm_status::kNormal);
}

TEST(PiperFirmware, EmergencyStopHaltsAndResumeNeedsTheModeAgain) {
  Harness h;
  h.enable_and_can_mode(100);
  h.targets({2.0, 0, 0, 0, 0, 0});
  h.run(0.3);
  ASSERT_GT(h.fw.truth().qd_radps[0], 2.9);
  MotionCommand stop;
  stop.estop = estop_action::kStop;
  h.send(encode_motion(stop));
  h.run(0.5);  // 3 rad/s at 10 rad/s^2 stops within 0.3 s
  EXPECT_EQ(h.fw.truth().qd_radps[0], 0.0);
  const double stopped_at = h.fw.truth().q_rad[0];
  EXPECT_LT(stopped_at, 2.0);
  EXPECT_EQ(h.status().arm_status, arm_status::kEmergencyStop);
  h.targets({0.0, 0, 0, 0, 0, 0});
  EXPECT_GT(h.fw.counters().targets_ignored, 0u);
  h.run(0.2);
  EXPECT_EQ(h.fw.truth().q_rad[0], stopped_at);
  MotionCommand resume;
  resume.estop = estop_action::kResume;
  h.send(encode_motion(resume));
  h.run(0.02);
  EXPECT_EQ(h.status().arm_status, arm_status::kNormal);
  EXPECT_EQ(h.status().ctrl_mode, ctrl_mode::kStandby);
  h.send(encode_mode(ModeCommand{}));
  h.targets({0.0, 0, 0, 0, 0, 0});
  h.run(2.0);
  EXPECT_EQ(h.fw.truth().q_rad[0], 0.0);
}

TEST(PiperFirmware, DisableStopsJointsAndClearsTheEnabledBits) {
  Harness h;
  h.enable_and_can_mode(100);
  h.send(encode_gripper(gripper_command(0.02, 1.0, gripper_code::kEnable)));
  h.targets({1.0, 0, 0, 0, 0, 0});
  h.run(0.2);
  h.send(encode_enable({kMotorAll, false}));
  const double q = h.fw.truth().q_rad[0];
  h.run(0.1);
  EXPECT_EQ(h.fw.truth().q_rad[0], q);
  for (int j = 0; j < kNumJoints; ++j) EXPECT_FALSE(h.low_speed(j).enabled());
  EXPECT_FALSE(h.fw.truth().gripper_enabled);
  // One joint only.
  h.send(encode_enable({2, true}));
  h.run(0.05);
  EXPECT_TRUE(h.low_speed(1).enabled());
  EXPECT_FALSE(h.low_speed(0).enabled());
}

TEST(PiperFirmware, GripperFollowsItsCommandWithinItsRange) {
  Harness h;
  h.send(encode_gripper(gripper_command(0.1, 2.0, gripper_code::kEnable)));  // clamped to 0.07
  h.run(0.5);
  EXPECT_NEAR(h.fw.truth().gripper_m, 0.025, 1e-9);  // 0.05 m/s
  h.run(1.5);
  EXPECT_DOUBLE_EQ(h.fw.truth().gripper_m, 0.07);
  GripperFeedback g;
  for (auto it = h.out.rbegin(); it != h.out.rend(); ++it) {
    if (decode_gripper_feedback(*it, g) == DecodeStatus::ok) break;
  }
  EXPECT_EQ(g.stroke_um, 70000);
  EXPECT_TRUE(g.enabled());
  GripperCommand zero = gripper_command(0.07, 1.0, gripper_code::kEnable);
  zero.set_zero = true;
  h.send(encode_gripper(zero));
  h.run(0.01);
  for (auto it = h.out.rbegin(); it != h.out.rend(); ++it) {
    if (decode_gripper_feedback(*it, g) == DecodeStatus::ok) break;
  }
  EXPECT_EQ(g.status & kGripperStatusZeroed, kGripperStatusZeroed);
}

TEST(PiperFirmware, PowerCycleComesBackDisabledInStandbyWhereItWas) {
  Harness h;
  h.enable_and_can_mode(100);
  h.targets({0.7, 0, 0, 0, 0, 0});
  h.run(1.0);
  h.fw.set_powered(false);
  const std::size_t before = h.out.size();
  h.run(0.5);
  EXPECT_EQ(h.out.size(), before);  // silent while off
  h.targets({0.0, 0, 0, 0, 0, 0});  // and deaf
  EXPECT_EQ(h.fw.counters().targets_ignored, 0u);
  h.fw.set_powered(true);
  h.run(0.05);
  EXPECT_EQ(h.status().ctrl_mode, ctrl_mode::kStandby);
  EXPECT_EQ(h.status().move_mode, move_mode::kMoveP);
  for (int j = 0; j < kNumJoints; ++j) EXPECT_FALSE(h.low_speed(j).enabled());
  EXPECT_DOUBLE_EQ(h.fw.truth().q_rad[0], mdeg_to_rad(rad_to_mdeg(0.7)));
  h.targets({0.0, 0, 0, 0, 0, 0});
  EXPECT_EQ(h.fw.counters().targets_ignored, 3u);
}

TEST(PiperFirmware, FaultHooksShowInTheFrames) {
  Harness h;
  h.fw.set_stream_enabled(FeedbackStream::joint_angles, false);
  h.fw.inject_err_code(err_comm_bit(4));
  h.fw.inject_arm_status(arm_status::kCollision);
  h.fw.inject_driver_status(2, 0x04);
  h.fw.inject_gripper_status(0x10);
  h.run(0.1);
  for (const CanFrame& f : h.out) {
    EXPECT_FALSE(f.id >= 0x2A5 && f.id <= 0x2A7) << "joint-angle stream should be stopped";
  }
  EXPECT_EQ(h.status().err_code, err_comm_bit(4));
  EXPECT_EQ(h.status().arm_status, arm_status::kCollision);
  EXPECT_EQ(h.low_speed(2).status, 0x04);
  h.fw.clear_injected_faults();
  h.fw.set_stream_enabled(FeedbackStream::joint_angles, true);
  h.out.clear();
  h.run(0.1);
  EXPECT_EQ(h.status().err_code, 0);
  EXPECT_EQ(h.status().arm_status, 0);
  EXPECT_EQ(h.low_speed(2).status, 0x00);
  int joint_frames = 0;
  for (const CanFrame& f : h.out) joint_frames += f.id >= 0x2A5 && f.id <= 0x2A7;
  EXPECT_EQ(joint_frames, 60);
}

TEST(PiperFirmware, MalformedCommandsAreCountedAndChangeNothing) {
  Harness h;
  CanFrame enable = encode_enable({kMotorAllJoints, true});
  enable.dlc = 1;
  h.send(enable);
  CanFrame mode = encode_mode(ModeCommand{});
  mode.data[2] = 200;  // speed > 100
  h.send(mode);
  h.run(0.1);
  EXPECT_EQ(h.fw.counters().frames_rejected, 2u);
  EXPECT_FALSE(h.fw.truth().joint_enabled[0]);
  EXPECT_EQ(h.fw.truth().ctrl_mode, ctrl_mode::kStandby);
}

TEST(PiperDh, HomePoseMatchesThePublishedOne) {
  const FlangePose pose = piper_flange_pose({0, 0, 0, 0, 0, 0});
  EXPECT_NEAR(pose.p_m[0], 0.056128, 2e-6);
  EXPECT_NEAR(pose.p_m[1], 0.0, 1e-9);
  EXPECT_NEAR(pose.p_m[2], 0.213266, 2e-6);
  EXPECT_NEAR(pose.rpy_rad[0], 0.0, 1e-9);
  EXPECT_NEAR(pose.rpy_rad[1], 85.0 * kPi / 180.0, 1e-6);
  EXPECT_NEAR(pose.rpy_rad[2], 0.0, 1e-9);
  // J1 turns the flange about the base z axis.
  const FlangePose turned = piper_flange_pose({kPi / 2, 0, 0, 0, 0, 0});
  EXPECT_NEAR(turned.p_m[0], 0.0, 2e-6);
  EXPECT_NEAR(turned.p_m[1], 0.056128, 2e-6);
  EXPECT_NEAR(turned.rpy_rad[2], kPi / 2, 1e-6);
  // The firmware's end-pose frames carry it (0.001 mm, 0.001 degree).
  Harness h;
  h.run(0.005);
  std::array<std::int32_t, 6> v{};
  for (const CanFrame& f : h.out) {
    EndPosePair p;
    if (decode_end_pose_pair(f, p) == DecodeStatus::ok) {
      v[2 * p.index] = p.value[0];
      v[2 * p.index + 1] = p.value[1];
    }
  }
  EXPECT_NEAR(v[0], 56128, 2);
  EXPECT_EQ(v[1], 0);
  EXPECT_NEAR(v[2], 213266, 2);
  EXPECT_EQ(v[4], 85000);
}

}  // namespace
}  // namespace porter::piper
