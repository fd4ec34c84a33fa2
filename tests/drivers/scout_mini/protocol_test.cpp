// Golden frames for every Scout Mini command and feedback layout: the manual's examples,
// big-endian byte order, signs, rounding, saturation, and decoders that refuse short, remote,
// extended or foreign frames.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "porter/scout_mini/protocol.hpp"

namespace porter::scout_mini {
namespace {

std::vector<int> bytes(const CanFrame& f) {
  std::vector<int> out;
  for (int i = 0; i < f.dlc; ++i) out.push_back(f.data[i]);
  return out;
}

CanFrame raw(std::uint32_t frame_id, std::vector<int> data) {
  CanFrame f;
  f.id = frame_id;
  for (int b : data) f.data[f.dlc++] = static_cast<std::uint8_t>(b);
  return f;
}

TEST(ScoutProtocol, ManualExamples) {
  MotionCommand forward;
  forward.v_mps = 0.15;
  const CanFrame f = encode_motion_command(forward);
  EXPECT_EQ(f.id, 0x111u);
  EXPECT_FALSE(f.extended);
  EXPECT_EQ(bytes(f), (std::vector<int>{0x00, 0x96, 0, 0, 0, 0, 0, 0}));
  MotionCommand turn;
  turn.omega_radps = 0.05;
  EXPECT_EQ(bytes(encode_motion_command(turn)), (std::vector<int>{0, 0, 0x00, 0x32, 0, 0, 0, 0}));
}

TEST(ScoutProtocol, MotionCommandSignsRoundingAndSaturation) {
  MotionCommand c;
  c.v_mps = -0.15;           // -150 = 0xFF6A
  c.omega_radps = -1.0;      // -1000 = 0xFC18
  c.lateral_mps = 0.0004;    // rounds to 0
  c.steering_rad = 0.0015;   // 1.5 rounds away from zero: 2
  EXPECT_EQ(bytes(encode_motion_command(c)),
            (std::vector<int>{0xFF, 0x6A, 0xFC, 0x18, 0x00, 0x00, 0x00, 0x02}));
  c = MotionCommand{};
  c.v_mps = 0.0289;          // 28.9 mm/s: nearest is 29 (truncation would give 28)
  c.omega_radps = -0.0289;
  EXPECT_EQ(bytes(encode_motion_command(c)), (std::vector<int>{0, 29, 0xFF, 0xE3, 0, 0, 0, 0}));
  c.v_mps = 40.0;            // beyond int16: saturates
  c.omega_radps = -40.0;
  c.lateral_mps = std::numeric_limits<double>::quiet_NaN();
  c.steering_rad = std::numeric_limits<double>::infinity();
  EXPECT_EQ(bytes(encode_motion_command(c)),
            (std::vector<int>{0x7F, 0xFF, 0x80, 0x00, 0, 0, 0x7F, 0xFF}));
  MotionCommand back;
  ASSERT_EQ(decode_motion_command(raw(0x111, {0xFF, 0x6A, 0x03, 0xE8}), back), DecodeStatus::ok);
  EXPECT_DOUBLE_EQ(back.v_mps, -0.15);
  EXPECT_DOUBLE_EQ(back.omega_radps, 1.0);
  EXPECT_EQ(back.lateral_mps, 0.0);
}

TEST(ScoutProtocol, ControlModeAndErrorClear) {
  EXPECT_EQ(bytes(encode_control_mode(ControlMode::can)), (std::vector<int>{1, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encode_control_mode(ControlMode::can).id, 0x421u);
  std::uint8_t mode = 9;
  EXPECT_EQ(decode_control_mode(raw(0x421, {0x01}), mode), DecodeStatus::ok);  // manual DLC 1
  EXPECT_EQ(mode, 1);
  EXPECT_EQ(decode_control_mode(raw(0x421, {}), mode), DecodeStatus::too_short);
  const CanFrame clear = encode_error_clear(2);
  EXPECT_EQ(clear.id, 0x441u);
  EXPECT_EQ(bytes(clear), (std::vector<int>{2}));
  std::uint8_t target = 0;
  EXPECT_EQ(decode_error_clear(clear, target), DecodeStatus::ok);
  EXPECT_EQ(target, 2);
}

TEST(ScoutProtocol, SystemState) {
  SystemState st;
  st.vehicle_state = 2;
  st.control_mode = 1;
  st.battery_voltage_v = 25.26;  // 252.6 -> 253 = 0x00FD
  st.error_bits = error_bit::kMotor2Comm | error_bit::kBatteryUnderVoltageWarning;
  st.count = 0xAB;
  const CanFrame f = encode_system_state(st);
  EXPECT_EQ(f.id, 0x211u);
  EXPECT_EQ(bytes(f), (std::vector<int>{0x02, 0x01, 0x00, 0xFD, 0x00, 0x12, 0x00, 0xAB}));
  SystemState back;
  ASSERT_EQ(decode_system_state(raw(0x211, {0, 3, 0x01, 0x04, 0x01, 0x01, 0, 7}), back),
            DecodeStatus::ok);
  EXPECT_EQ(back.control_mode, 3);
  EXPECT_DOUBLE_EQ(back.battery_voltage_v, 26.0);
  EXPECT_EQ(back.error_bits, 0x0101);
  EXPECT_EQ(back.count, 7);
  EXPECT_EQ(error_names(back.error_bits), "battery_under_voltage_fault, motor_driver");
  EXPECT_EQ(error_names(0x8000), "bit15");
  EXPECT_EQ(error_names(0), "");
}

TEST(ScoutProtocol, MotionStateBigEndianAndSign) {
  MotionState st;
  ASSERT_EQ(decode_motion_state(raw(0x221, {0x01, 0x2C, 0xFF, 0x38, 0, 0, 0, 0}), st),
            DecodeStatus::ok);
  EXPECT_DOUBLE_EQ(st.v_mps, 0.3);
  EXPECT_DOUBLE_EQ(st.omega_radps, -0.2);
  st.v_mps = -0.0625;  // -62.5 (exact in binary): the tie goes away from zero, -63 = 0xFFC1
  st.omega_radps = 0.0625;
  EXPECT_EQ(bytes(encode_motion_state(st)), (std::vector<int>{0xFF, 0xC1, 0x00, 0x3F, 0, 0, 0, 0}));
}

TEST(ScoutProtocol, ActuatorFrames) {
  ActuatorHighSpeed hs;
  hs.motor = 2;
  hs.speed_rpm = -1500.4;
  hs.current_a = 3.25;  // 32.5 -> 33
  hs.pulse_count = -2;
  const CanFrame f = encode_actuator_high_speed(hs);
  EXPECT_EQ(f.id, 0x253u);
  EXPECT_EQ(bytes(f), (std::vector<int>{0xFA, 0x24, 0x00, 0x21, 0xFF, 0xFF, 0xFF, 0xFE}));
  ActuatorHighSpeed back;
  ASSERT_EQ(decode_actuator_high_speed(raw(0x254, {0, 100, 0xFF, 0xF6, 0x12, 0x34, 0x56, 0x78}), back),
            DecodeStatus::ok);
  EXPECT_EQ(back.motor, 3);
  EXPECT_EQ(back.speed_rpm, 100);
  EXPECT_DOUBLE_EQ(back.current_a, -1.0);
  EXPECT_EQ(back.pulse_count, 0x12345678);

  ActuatorLowSpeed ls;
  ls.motor = 0;
  ls.driver_voltage_v = 24.8;
  ls.driver_temperature_c = -5;
  ls.motor_temperature_c = -40;
  ls.driver_status = driver_bit::kMotorOverheat | driver_bit::kDriverEnabled;
  const CanFrame g = encode_actuator_low_speed(ls);
  EXPECT_EQ(g.id, 0x261u);
  EXPECT_EQ(bytes(g), (std::vector<int>{0x00, 0xF8, 0xFF, 0xFB, 0xD8, 0x42, 0, 0}));
  ActuatorLowSpeed lb;
  ASSERT_EQ(decode_actuator_low_speed(g, lb), DecodeStatus::ok);
  EXPECT_DOUBLE_EQ(lb.driver_voltage_v, 24.8);
  EXPECT_EQ(lb.driver_temperature_c, -5);
  EXPECT_EQ(lb.motor_temperature_c, -40);
  EXPECT_EQ(driver_status_names(lb.driver_status), "motor_overheat, driver_enabled");
}

TEST(ScoutProtocol, OdometryAndBms) {
  Odometry o;
  o.left_mm = 1000;
  o.right_mm = -1;
  const CanFrame f = encode_odometry(o);
  EXPECT_EQ(f.id, 0x311u);
  EXPECT_EQ(bytes(f), (std::vector<int>{0x00, 0x00, 0x03, 0xE8, 0xFF, 0xFF, 0xFF, 0xFF}));
  Odometry back;
  ASSERT_EQ(decode_odometry(raw(0x311, {0x80, 0, 0, 0, 0x7F, 0xFF, 0xFF, 0xFF}), back),
            DecodeStatus::ok);
  EXPECT_EQ(back.left_mm, std::numeric_limits<std::int32_t>::min());
  EXPECT_EQ(back.right_mm, std::numeric_limits<std::int32_t>::max());
  BmsBasic b;
  ASSERT_EQ(decode_bms_basic(raw(0x361, {87, 99, 0x00, 0xFC, 0xFF, 0xEC, 0x00, 0xFA}), b),
            DecodeStatus::ok);
  EXPECT_EQ(b.soc_pct, 87);
  EXPECT_EQ(b.soh_pct, 99);
  EXPECT_DOUBLE_EQ(b.voltage_v, 25.2);
  EXPECT_DOUBLE_EQ(b.current_a, -2.0);
  EXPECT_DOUBLE_EQ(b.temperature_c, 25.0);
}

TEST(ScoutProtocol, DecodersRefuseWhatIsNotTheirFrame) {
  MotionState st;
  EXPECT_EQ(decode_motion_state(raw(0x222, {0, 0, 0, 0}), st), DecodeStatus::wrong_id);
  EXPECT_EQ(decode_motion_state(raw(0x221, {0, 0, 0}), st), DecodeStatus::too_short);
  CanFrame remote = raw(0x221, {});
  remote.rtr = true;
  remote.dlc = 8;  // a remote frame claims a length but carries no data
  EXPECT_EQ(decode_motion_state(remote, st), DecodeStatus::remote_frame);
  CanFrame ext = raw(0x221, {0, 0, 0, 0, 0, 0, 0, 0});
  ext.extended = true;
  EXPECT_EQ(decode_motion_state(ext, st), DecodeStatus::extended_id);
  Odometry o;
  EXPECT_EQ(decode_odometry(raw(0x311, {1, 2, 3, 4, 5, 6, 7}), o), DecodeStatus::too_short);
  ActuatorHighSpeed hs;
  EXPECT_EQ(decode_actuator_high_speed(raw(0x255, {0, 0, 0, 0, 0, 0, 0, 0}), hs),
            DecodeStatus::wrong_id);
  ActuatorLowSpeed ls;
  EXPECT_EQ(decode_actuator_low_speed(raw(0x264, {0, 0, 0, 0, 0}), ls), DecodeStatus::too_short);
  SystemState sys;
  CanFrame bad_dlc = raw(0x211, {0, 0, 0, 0, 0, 0, 0, 0});
  bad_dlc.dlc = 15;  // never read past the 8 data bytes
  EXPECT_EQ(decode_system_state(bad_dlc, sys), DecodeStatus::too_short);
}

TEST(ScoutProtocol, ProtocolHints) {
  EXPECT_EQ(protocol_hint(raw(0x151, {})), ProtocolHint::v1);
  EXPECT_EQ(protocol_hint(raw(0x221, {})), ProtocolHint::v2);
  EXPECT_EQ(protocol_hint(raw(0x241, {})), ProtocolHint::v2);
  EXPECT_EQ(protocol_hint(raw(0x211, {})), ProtocolHint::none);
  CanFrame ext = raw(0x151, {});
  ext.extended = true;
  EXPECT_EQ(protocol_hint(ext), ProtocolHint::none);
}

TEST(ScoutProtocol, ScaleRoundIsNearestWithTiesAwayFromZero) {
  EXPECT_EQ(scale_round(0.5, 1.0, -10, 10), 1);
  EXPECT_EQ(scale_round(-0.5, 1.0, -10, 10), -1);
  EXPECT_EQ(scale_round(0.49, 1.0, -10, 10), 0);
  EXPECT_EQ(scale_round(100.0, 1.0, -10, 10), 10);
  EXPECT_EQ(scale_round(-100.0, 1.0, -10, 10), -10);
  EXPECT_EQ(scale_round(std::nan(""), 1.0, -10, 10), 0);
}

}  // namespace
}  // namespace porter::scout_mini
