// Golden frames for every Piper feedback layout (byte order, signed and unsigned fields, units),
// fault names, and the decoders' refusal of short, long, extended and foreign frames.
#include <gtest/gtest.h>

#include <initializer_list>
#include <random>

#include "porter/piper/faults.hpp"
#include "porter/piper/feedback.hpp"

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

TEST(PiperFeedback, StatusGoldenAndErrorNames) {
  // CAN mode, collision, MOVE J, moving; err_code B6 = 0x04 (joint 3 angle limit),
  // B7 = 0x02 (joint 2 communication error).
  const CanFrame f = frame(0x2A1, {0x01, 0x07, 0x01, 0x00, 0x01, 0x00, 0x04, 0x02});
  StatusFeedback s;
  ASSERT_EQ(decode_status(f, s), DecodeStatus::ok);
  EXPECT_EQ(s.ctrl_mode, 0x01);
  EXPECT_EQ(s.arm_status, arm_status::kCollision);
  EXPECT_EQ(s.move_mode, 0x01);
  EXPECT_EQ(s.motion_status, 1);
  EXPECT_EQ(s.err_code, 0x0402);
  EXPECT_EQ(encode_status(s), f);
  EXPECT_EQ(s.err_code, err_angle_limit_bit(2) | err_comm_bit(1));
  std::vector<std::string> names;
  append_err_code_names(s.err_code, names);
  EXPECT_EQ(join_names(names), "joint2_comm_error, joint3_angle_limit");
  EXPECT_STREQ(arm_status_name(s.arm_status), "collision");
  EXPECT_STREQ(ctrl_mode_name(s.ctrl_mode), "can");
  EXPECT_STREQ(move_mode_name(s.move_mode), "move_j");
  names.clear();
  append_err_code_names(0xC0C0, names);  // reserved bits still named, never dropped
  EXPECT_EQ(join_names(names), "err_code_bit6, err_code_bit7, err_code_bit14, err_code_bit15");
}

TEST(PiperFeedback, ArmStatusNamesAndWhichAreFaults) {
  EXPECT_STREQ(arm_status_name(0x00), "normal");
  EXPECT_STREQ(arm_status_name(0x01), "emergency_stop");
  EXPECT_STREQ(arm_status_name(0x04), "target_exceeds_limit");
  EXPECT_STREQ(arm_status_name(0x0F), "discharge_resistor_over_temperature");
  EXPECT_STREQ(arm_status_name(0x42), "unknown");
  EXPECT_FALSE(arm_status_is_fault(0x00));
  EXPECT_FALSE(arm_status_is_fault(0x0C));  // teach execution
  EXPECT_TRUE(arm_status_is_fault(0x01));
  EXPECT_TRUE(arm_status_is_fault(0x07));
  EXPECT_TRUE(arm_status_is_fault(0x42));
  EXPECT_STREQ(ctrl_mode_name(0x00), "standby");
  EXPECT_STREQ(ctrl_mode_name(0x09), "unknown");
}

TEST(PiperFeedback, JointAnglesGolden) {
  // J1 = +pi/2 (0x00015F90), J2 = -pi/2 (0xFFFEA070) on 0x2A5; J5 = -1 mdeg, J6 = +1 mdeg on 0x2A7.
  JointAnglePair p;
  ASSERT_EQ(decode_joint_angle_pair(frame(0x2A5, {0x00, 0x01, 0x5F, 0x90, 0xFF, 0xFE, 0xA0, 0x70}), p),
            DecodeStatus::ok);
  EXPECT_EQ(p.first, 0);
  EXPECT_DOUBLE_EQ(mdeg_to_rad(p.mdeg[0]), kPi / 2);
  EXPECT_DOUBLE_EQ(mdeg_to_rad(p.mdeg[1]), -kPi / 2);
  ASSERT_EQ(decode_joint_angle_pair(frame(0x2A7, {0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x01}), p),
            DecodeStatus::ok);
  EXPECT_EQ(p.first, 4);
  EXPECT_EQ(p.mdeg[0], -1);
  EXPECT_EQ(p.mdeg[1], 1);
  EXPECT_EQ(encode_joint_angle_pair(p), frame(0x2A7, {0xFF, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x01}));
}

TEST(PiperFeedback, EndPoseGolden) {
  // (Z, RX) = (213.266 mm, -0.5 deg) -> 213266 = 0x00034112, -500 = 0xFFFFFE0C.
  EndPosePair p;
  ASSERT_EQ(decode_end_pose_pair(frame(0x2A3, {0x00, 0x03, 0x41, 0x12, 0xFF, 0xFF, 0xFE, 0x0C}), p),
            DecodeStatus::ok);
  EXPECT_EQ(p.index, 1);
  EXPECT_EQ(p.value[0], 213266);
  EXPECT_EQ(p.value[1], -500);
  EXPECT_EQ(encode_end_pose_pair(p), frame(0x2A3, {0x00, 0x03, 0x41, 0x12, 0xFF, 0xFF, 0xFE, 0x0C}));
}

TEST(PiperFeedback, GripperGolden) {
  // 35 000 µm, effort -200 mN·m (0xFF38), enabled + zeroed, over-current; B7 unused (7 bytes ok).
  GripperFeedback g;
  CanFrame f = frame(0x2A8, {0x00, 0x00, 0x88, 0xB8, 0xFF, 0x38, 0xC4});
  ASSERT_EQ(decode_gripper_feedback(f, g), DecodeStatus::ok);
  EXPECT_DOUBLE_EQ(g.stroke_m(), 0.035);
  EXPECT_DOUBLE_EQ(g.effort_nm(), -0.2);
  EXPECT_TRUE(g.enabled());
  EXPECT_EQ(g.status, 0xC4);
  std::vector<std::string> names;
  append_gripper_status_names(g.status & kGripperFaultMask, "gripper_", names);
  EXPECT_EQ(join_names(names), "gripper_over_current");
  f.dlc = 6;
  EXPECT_EQ(decode_gripper_feedback(f, g), DecodeStatus::short_frame);
}

TEST(PiperFeedback, HighSpeedGolden) {
  // Motor 3: -1.000 rad/s (0xFC18), 0.500 A (0x01F4), position 1000.
  HighSpeedFeedback h;
  const CanFrame f = frame(0x253, {0xFC, 0x18, 0x01, 0xF4, 0x00, 0x00, 0x03, 0xE8});
  ASSERT_EQ(decode_high_speed(f, h), DecodeStatus::ok);
  EXPECT_EQ(h.joint, 2);
  EXPECT_DOUBLE_EQ(h.speed_radps(), -1.0);
  EXPECT_DOUBLE_EQ(h.current_a(), 0.5);
  EXPECT_EQ(h.position_raw, 1000);
  EXPECT_EQ(encode_high_speed(h), f);
  EXPECT_DOUBLE_EQ(kTorqueConstantNmPerA[2], 1.18125);
  EXPECT_DOUBLE_EQ(kTorqueConstantNmPerA[3], 0.95844);
  EXPECT_EQ(decode_high_speed(frame(0x257, {0, 0, 0, 0, 0, 0, 0, 0}), h), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_high_speed(frame(0x250, {0, 0, 0, 0, 0, 0, 0, 0}), h), DecodeStatus::wrong_id);
}

TEST(PiperFeedback, LowSpeedGoldenUnsignedAndSignedFields) {
  // Motor 4: 24.0 V (0x00F0), driver -10 °C (0xFFF6), motor -30 °C (0xE2), status enabled +
  // under-voltage + over-current (0x45), bus current 65.535 A (0xFFFF, unsigned).
  LowSpeedFeedback l;
  const CanFrame f = frame(0x264, {0x00, 0xF0, 0xFF, 0xF6, 0xE2, 0x45, 0xFF, 0xFF});
  ASSERT_EQ(decode_low_speed(f, l), DecodeStatus::ok);
  EXPECT_EQ(l.joint, 3);
  EXPECT_EQ(l.voltage_dv, 240);
  EXPECT_EQ(l.driver_temp_c, -10);
  EXPECT_EQ(l.motor_temp_c, -30);
  EXPECT_TRUE(l.enabled());
  EXPECT_EQ(l.bus_current_ma, 65535);
  EXPECT_EQ(encode_low_speed(l), f);
  std::vector<std::string> names;
  append_driver_status_names(l.status & kDriverFaultMask, "joint4_", names);
  EXPECT_EQ(join_names(names), "joint4_under_voltage, joint4_over_current");
  names.clear();
  append_driver_status_names(0xFF, "", names);
  EXPECT_EQ(names.size(), 7u);  // every bit but "enabled"
  EXPECT_EQ(names.back(), "stall_protection");
}

TEST(PiperFeedback, DecodersRefuseShortLongExtendedAndForeignFrames) {
  StatusFeedback s;
  JointAnglePair j;
  HighSpeedFeedback h;
  LowSpeedFeedback l;
  EndPosePair e;
  for (std::uint32_t id : {0x2A1u, 0x2A2u, 0x2A5u, 0x251u, 0x261u}) {
    for (std::uint8_t dlc = 0; dlc < 8; ++dlc) {
      CanFrame f = frame(id, {0, 0, 0, 0, 0, 0, 0, 0});
      f.dlc = dlc;
      DecodeStatus got = DecodeStatus::ok;
      if (id == 0x2A1) got = decode_status(f, s);
      if (id == 0x2A2) got = decode_end_pose_pair(f, e);
      if (id == 0x2A5) got = decode_joint_angle_pair(f, j);
      if (id == 0x251) got = decode_high_speed(f, h);
      if (id == 0x261) got = decode_low_speed(f, l);
      EXPECT_EQ(got, DecodeStatus::short_frame) << std::hex << id << " dlc " << int(dlc);
    }
  }
  CanFrame f = frame(0x2A1, {0, 0, 0, 0, 0, 0, 0, 0});
  f.dlc = 15;
  EXPECT_EQ(decode_status(f, s), DecodeStatus::bad_dlc);
  f.dlc = 8;
  f.extended = true;
  EXPECT_EQ(decode_status(f, s), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_status(frame(0x2A5, {0, 0, 0, 0, 0, 0, 0, 0}), s), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_joint_angle_pair(frame(0x2A8, {0, 0, 0, 0, 0, 0, 0, 0}), j), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_low_speed(frame(0x267, {0, 0, 0, 0, 0, 0, 0, 0}), l), DecodeStatus::wrong_id);
}

TEST(PiperFeedback, EveryLayoutRoundTripsRandomValues) {
  std::mt19937 rng(3);
  auto u8 = [&] { return static_cast<std::uint8_t>(rng()); };
  auto i32 = [&] { return static_cast<std::int32_t>(rng()); };
  auto i16 = [&] { return static_cast<std::int16_t>(rng()); };
  for (int trial = 0; trial < 500; ++trial) {
    StatusFeedback s{u8(), u8(), u8(), u8(), u8(), u8(), static_cast<std::uint16_t>(rng())}, s2;
    ASSERT_EQ(decode_status(encode_status(s), s2), DecodeStatus::ok);
    EXPECT_EQ(encode_status(s2), encode_status(s));
    JointAnglePair j{2 * static_cast<int>(rng() % 3), {i32(), i32()}}, j2;
    ASSERT_EQ(decode_joint_angle_pair(encode_joint_angle_pair(j), j2), DecodeStatus::ok);
    EXPECT_EQ(j2.first, j.first);
    EXPECT_EQ(j2.mdeg, j.mdeg);
    GripperFeedback g{i32(), i16(), u8()}, g2;
    ASSERT_EQ(decode_gripper_feedback(encode_gripper_feedback(g), g2), DecodeStatus::ok);
    EXPECT_EQ(g2.stroke_um, g.stroke_um);
    EXPECT_EQ(g2.effort_mnm, g.effort_mnm);
    EXPECT_EQ(g2.status, g.status);
    HighSpeedFeedback h{static_cast<int>(rng() % 6), i16(), i16(), i32()}, h2;
    ASSERT_EQ(decode_high_speed(encode_high_speed(h), h2), DecodeStatus::ok);
    EXPECT_EQ(h2.joint, h.joint);
    EXPECT_EQ(h2.speed_mradps, h.speed_mradps);
    EXPECT_EQ(h2.current_ma, h.current_ma);
    EXPECT_EQ(h2.position_raw, h.position_raw);
    LowSpeedFeedback l{static_cast<int>(rng() % 6), static_cast<std::uint16_t>(rng()), i16(),
                       static_cast<std::int8_t>(rng()), u8(), static_cast<std::uint16_t>(rng())}, l2;
    ASSERT_EQ(decode_low_speed(encode_low_speed(l), l2), DecodeStatus::ok);
    EXPECT_EQ(encode_low_speed(l2), encode_low_speed(l));
    EXPECT_EQ(l2.joint, l.joint);
  }
}

}  // namespace
}  // namespace porter::piper
