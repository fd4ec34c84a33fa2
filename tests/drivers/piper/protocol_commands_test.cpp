// Golden frames for every Piper command layout (byte order, signs, rounding, clamping) and the
// command decoders the firmware model uses.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <random>

#include "porter/piper/commands.hpp"

namespace porter::piper {
namespace {

using can::CanFrame;

CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  for (std::uint8_t b : bytes) f.data[f.dlc++] = b;
  return f;
}

constexpr double kPi = 3.14159265358979323846;

TEST(PiperCommands, EnableGolden) {
  EXPECT_EQ(encode_enable({kMotorAllJoints, true}), frame(0x471, {0x07, 0x02, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode_enable({kMotorAll, false}), frame(0x471, {0xFF, 0x01, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode_enable({3, true}), frame(0x471, {0x03, 0x02, 0, 0, 0, 0, 0, 0}));
  EnableCommand e;
  ASSERT_EQ(decode_enable(frame(0x471, {0x05, 0x01}), e), DecodeStatus::ok);
  EXPECT_EQ(e.motor, 5);
  EXPECT_FALSE(e.enable);
  EXPECT_EQ(decode_enable(frame(0x471, {0x05, 0x03}), e), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_enable(frame(0x471, {0x00, 0x02}), e), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_enable(frame(0x471, {0x08, 0x02}), e), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_enable(frame(0x471, {0x07}), e), DecodeStatus::short_frame);
}

TEST(PiperCommands, ModeGolden) {
  ModeCommand m;  // CAN, MOVE J, 50 %
  EXPECT_EQ(encode_mode(m), frame(0x151, {0x01, 0x01, 0x32, 0x00, 0x00, 0x00, 0, 0}));
  m.speed_pct = 150;  // clamped to 100
  m.ctrl_mode = ctrl_mode::kStandby;
  m.installation = 0x01;
  EXPECT_EQ(encode_mode(m), frame(0x151, {0x00, 0x01, 0x64, 0x00, 0x00, 0x01, 0, 0}));
  ModeCommand d;
  ASSERT_EQ(decode_mode(frame(0x151, {0x01, 0x01, 0x1E, 0x00, 0x00, 0x00, 0, 0}), d), DecodeStatus::ok);
  EXPECT_EQ(d.ctrl_mode, ctrl_mode::kCan);
  EXPECT_EQ(d.move_mode, move_mode::kMoveJ);
  EXPECT_EQ(d.speed_pct, 30);
  EXPECT_EQ(decode_mode(frame(0x151, {0x01, 0x01, 0x65, 0, 0, 0, 0, 0}), d), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_mode(frame(0x151, {0x01, 0x01, 0x10, 0, 0}), d), DecodeStatus::short_frame);
}

TEST(PiperCommands, EmergencyStopGolden) {
  MotionCommand m;
  m.estop = estop_action::kStop;
  EXPECT_EQ(encode_motion(m), frame(0x150, {0x01, 0, 0, 0, 0, 0, 0, 0}));
  m.estop = estop_action::kResume;
  EXPECT_EQ(encode_motion(m), frame(0x150, {0x02, 0, 0, 0, 0, 0, 0, 0}));
  MotionCommand d;
  ASSERT_EQ(decode_motion(frame(0x150, {0x01, 0x00, 0x00, 0, 0, 0, 0, 0}), d), DecodeStatus::ok);
  EXPECT_EQ(d.estop, estop_action::kStop);
  EXPECT_EQ(decode_motion(frame(0x150, {0x03, 0, 0, 0, 0, 0, 0, 0}), d), DecodeStatus::invalid_value);
}

TEST(PiperCommands, JointTargetsGoldenBigEndianAndSigns) {
  // J1 = +pi/2 -> 90 000 mdeg = 0x00015F90; J2 = -pi/2 -> -90 000 = 0xFFFEA070;
  // J3 = 0.1 rad -> 5729.578 -> 5730 = 0x1662; J4 = -0.5 rad -> -28647.89 -> -28648 = 0xFFFF9018;
  // J5 = pi -> 180 000 = 0x0002BF20; J6 = 1 rad -> 57295.78 -> 57296 = 0xDFD0 (57325 if 3.14 were pi).
  const auto frames = encode_joint_targets({kPi / 2, -kPi / 2, 0.1, -0.5, kPi, 1.0});
  EXPECT_EQ(frames[0], frame(0x155, {0x00, 0x01, 0x5F, 0x90, 0xFF, 0xFE, 0xA0, 0x70}));
  EXPECT_EQ(frames[1], frame(0x156, {0x00, 0x00, 0x16, 0x62, 0xFF, 0xFF, 0x90, 0x18}));
  EXPECT_EQ(frames[2], frame(0x157, {0x00, 0x02, 0xBF, 0x20, 0x00, 0x00, 0xDF, 0xD0}));
  JointPair p;
  ASSERT_EQ(decode_joint_target_pair(frames[1], p), DecodeStatus::ok);
  EXPECT_EQ(p.first, 2);
  EXPECT_EQ(p.mdeg[0], 5730);
  EXPECT_EQ(p.mdeg[1], -28648);
}

TEST(PiperCommands, JointTargetsRoundToNearestSymmetrically) {
  const double per_mdeg = 1.0 / kMilliDegPerRad;
  EXPECT_EQ(rad_to_mdeg(1.4999 * per_mdeg), 1);
  EXPECT_EQ(rad_to_mdeg(1.5001 * per_mdeg), 2);
  EXPECT_EQ(rad_to_mdeg(-1.4999 * per_mdeg), -1);
  EXPECT_EQ(rad_to_mdeg(-1.5001 * per_mdeg), -2);
  EXPECT_EQ(rad_to_mdeg(0.4 * per_mdeg), 0);
  EXPECT_EQ(rad_to_mdeg(-0.4 * per_mdeg), 0);
  // The exact constant: 1000 * 180 / pi, not 1000 * 180 / 3.14.
  EXPECT_DOUBLE_EQ(kMilliDegPerRad, 1000.0 * 180.0 / kPi);
  EXPECT_EQ(rad_to_mdeg(1.0), 57296);
  // Saturation and NaN.
  EXPECT_EQ(rad_to_mdeg(1e9), 2147483647);
  EXPECT_EQ(rad_to_mdeg(-1e9), -2147483647 - 1);
  EXPECT_EQ(rad_to_mdeg(std::nan("")), 0);
  const auto frames = encode_joint_targets({1e9, 0, 0, 0, 0, 0});
  EXPECT_EQ(frames[0], frame(0x155, {0x7F, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0}));
}

TEST(PiperCommands, JointTargetsRoundTripWithinHalfAMillidegree) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> q(-3.2, 3.2);
  for (int trial = 0; trial < 1000; ++trial) {
    std::array<double, kNumJoints> in;
    for (double& v : in) v = q(rng);
    const auto frames = encode_joint_targets(in);
    for (const CanFrame& f : frames) {
      JointPair p;
      ASSERT_EQ(decode_joint_target_pair(f, p), DecodeStatus::ok);
      for (int k = 0; k < 2; ++k) {
        EXPECT_LE(std::abs(mdeg_to_rad(p.mdeg[k]) - in[p.first + k]), 0.5 / kMilliDegPerRad + 1e-15);
      }
    }
  }
}

TEST(PiperCommands, GripperGolden) {
  // 0.035 m -> 35 000 µm = 0x88B8; 1.5 N·m -> 1500 = 0x05DC; enable.
  EXPECT_EQ(encode_gripper(gripper_command(0.035, 1.5, gripper_code::kEnable)),
            frame(0x159, {0x00, 0x00, 0x88, 0xB8, 0x05, 0xDC, 0x01, 0x00}));
  // Effort above 5 N·m is clamped to 5000; below zero to 0; set-zero byte.
  GripperCommand g = gripper_command(0.0704996, 7.0, gripper_code::kEnableClearError);
  EXPECT_EQ(g.stroke_um, 70500);
  g.set_zero = true;
  EXPECT_EQ(encode_gripper(g), frame(0x159, {0x00, 0x01, 0x13, 0x64, 0x13, 0x88, 0x03, 0xAE}));
  EXPECT_EQ(gripper_command(0.01, -1.0, gripper_code::kEnable).effort_mnm, 0);
  GripperCommand d;
  ASSERT_EQ(decode_gripper(frame(0x159, {0xFF, 0xFF, 0xFF, 0x9C, 0x00, 0x64, 0x00, 0x00}), d), DecodeStatus::ok);
  EXPECT_EQ(d.stroke_um, -100);
  EXPECT_EQ(d.effort_mnm, 100);
  EXPECT_EQ(d.code, gripper_code::kDisable);
  EXPECT_FALSE(d.set_zero);
  EXPECT_EQ(decode_gripper(frame(0x159, {0, 0, 0, 0, 0x13, 0x89, 0x01, 0x00}), d), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_gripper(frame(0x159, {0, 0, 0, 0, 0, 0, 0x04, 0x00}), d), DecodeStatus::invalid_value);
  EXPECT_EQ(decode_gripper(frame(0x159, {0, 0, 0, 0, 0, 0, 0x01, 0x12}), d), DecodeStatus::invalid_value);
}

TEST(PiperCommands, DecodersRefuseOtherFramesAndNeverTrustTheDlc) {
  EnableCommand e;
  ModeCommand m;
  MotionCommand mo;
  JointPair p;
  GripperCommand g;
  CanFrame f = frame(0x155, {1, 2, 3, 4, 5, 6, 7});  // one byte short; data[7] holds garbage
  f.data[7] = 0xEE;
  EXPECT_EQ(decode_joint_target_pair(f, p), DecodeStatus::short_frame);
  f.dlc = 9;
  EXPECT_EQ(decode_joint_target_pair(f, p), DecodeStatus::bad_dlc);
  f.dlc = 8;
  f.extended = true;
  EXPECT_EQ(decode_joint_target_pair(f, p), DecodeStatus::wrong_id);
  f.extended = false;
  f.rtr = true;
  EXPECT_EQ(decode_joint_target_pair(f, p), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_joint_target_pair(frame(0x158, {0, 0, 0, 0, 0, 0, 0, 0}), p), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_enable(frame(0x151, {7, 2}), e), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_mode(frame(0x150, {1, 1, 1, 0, 0, 0}), m), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_motion(frame(0x150, {1, 0}), mo), DecodeStatus::short_frame);
  EXPECT_EQ(decode_gripper(frame(0x159, {0, 0, 0, 0, 0, 0, 1}), g), DecodeStatus::short_frame);
  EXPECT_EQ(decode_enable(frame(0x471, {}), e), DecodeStatus::short_frame);
}

}  // namespace
}  // namespace porter::piper
