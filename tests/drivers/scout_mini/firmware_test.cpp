// The Scout Mini firmware model on its own: standby until 0x421, the 0x111 response (saturation,
// acceleration limit, lag, no overshoot), the 500 ms command timeout, stream rates independent
// of the caller's step, pose integration, faults, power cycles and a bounded input queue.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "porter/scout_mini/firmware.hpp"

namespace porter::scout_mini {
namespace {

CanFrame motion(double v, double w) {
  MotionCommand c;
  c.v_mps = v;
  c.omega_radps = w;
  return encode_motion_command(c);
}

// Feeds `command` every 20 ms from t0 to t1 while advancing in 1 ms steps.
void drive(ScoutMiniFirmware& fw, double t0, double t1, const CanFrame& command,
           std::vector<CanFrame>* out = nullptr) {
  std::vector<CanFrame> sink;
  for (long k = std::lround(t0 * 1000) + 1; k <= std::lround(t1 * 1000); ++k) {
    const double t = k * 1e-3;
    if (k % 20 == 0) fw.receive(command, t);
    fw.advance(t, out ? *out : sink);
  }
}

void idle(ScoutMiniFirmware& fw, double t1, std::vector<CanFrame>* out = nullptr) {
  std::vector<CanFrame> sink;
  fw.advance(t1, out ? *out : sink);
}

SystemState last_system_state(const std::vector<CanFrame>& frames) {
  SystemState st;
  for (const CanFrame& f : frames) {
    if (f.id == id::kSystemState) decode_system_state(f, st);
  }
  return st;
}

TEST(ScoutFirmware, StandbyUntilControlModeFrame) {
  ScoutMiniFirmware fw;
  std::vector<CanFrame> out;
  drive(fw, 0.0, 0.5, motion(0.5, 0.0), &out);
  EXPECT_EQ(fw.mode(), ControlMode::standby);
  EXPECT_EQ(fw.v_mps(), 0.0);
  EXPECT_EQ(last_system_state(out).control_mode, 0);
  EXPECT_GT(fw.frames_ignored(), 20u);
  fw.receive(encode_control_mode(ControlMode::can), 0.5);
  out.clear();
  drive(fw, 0.5, 1.0, motion(0.5, 0.0), &out);
  EXPECT_EQ(fw.mode(), ControlMode::can);
  EXPECT_EQ(last_system_state(out).control_mode, 1);
  EXPECT_GT(fw.v_mps(), 0.3);
  // Serial mode: CAN motion commands are ignored again.
  fw.receive(encode_control_mode(ControlMode::serial), 1.0);
  drive(fw, 1.0, 2.0, motion(0.5, 0.0));
  EXPECT_EQ(fw.mode(), ControlMode::serial);
  EXPECT_EQ(fw.v_mps(), 0.0);
}

TEST(ScoutFirmware, FollowsCommandsWithinAccelerationLimitsWithoutOvershoot) {
  FirmwareParams p;
  ScoutMiniFirmware fw(p);
  fw.receive(encode_control_mode(ControlMode::can), 0.0);
  double prev = 0.0;
  double max_accel = 0.0;
  double t_reach = -1.0;
  std::vector<CanFrame> sink;
  for (int k = 1; k <= 2000; ++k) {
    const double t = k * 1e-3;
    if (k % 20 == 0) fw.receive(motion(1.0, 0.0), t);
    fw.advance(t, sink);
    max_accel = std::max(max_accel, (fw.v_mps() - prev) / 1e-3);
    EXPECT_LE(fw.v_mps(), 1.0 + 1e-12);
    EXPECT_GE(fw.v_mps(), prev - 1e-12);
    if (t_reach < 0 && fw.v_mps() == 1.0) t_reach = t;
    prev = fw.v_mps();
  }
  EXPECT_LE(max_accel, p.linear_accel_max_mps2 + 1e-6);
  // 1 m/s at 1.5 m/s^2 takes 0.67 s; the lag's tail adds about tau * ln(a tau / settle).
  EXPECT_GT(t_reach, 0.66);
  EXPECT_LT(t_reach, 1.0);
  // Saturation at the firmware's limits.
  drive(fw, 2.0, 5.0, motion(9.0, -9.0));
  EXPECT_DOUBLE_EQ(fw.v_mps(), p.v_max_mps);
  EXPECT_DOUBLE_EQ(fw.omega_radps(), -p.omega_max_radps);
}

TEST(ScoutFirmware, StopsWhenCommandsStopFor500ms) {
  ScoutMiniFirmware fw;
  fw.receive(encode_control_mode(ControlMode::can), 0.0);
  drive(fw, 0.0, 1.0, motion(0.4, 0.3));  // last command at t = 1.0
  idle(fw, 1.49);
  EXPECT_DOUBLE_EQ(fw.target().v_mps, 0.4);
  idle(fw, 1.501);
  EXPECT_EQ(fw.target().v_mps, 0.0);
  EXPECT_EQ(fw.target().omega_radps, 0.0);
  idle(fw, 2.5);
  EXPECT_EQ(fw.v_mps(), 0.0);
  EXPECT_EQ(fw.omega_radps(), 0.0);
}

TEST(ScoutFirmware, StreamsAtTheirRatesWhateverTheCallRate) {
  for (double step : {0.001, 0.007, 0.05, 1.0}) {
    ScoutMiniFirmware fw;
    std::vector<CanFrame> out;
    for (int k = 1; k * step < 1.0 + step - 1e-9; ++k) fw.advance(std::min(k * step, 1.0), out);
    std::map<std::uint32_t, int> count;
    for (const CanFrame& f : out) {
      ++count[f.id];
      // Stamped on the stream's own grid.
      EXPECT_EQ(f.utime % 20000, 0) << std::hex << f.id;
    }
    EXPECT_EQ(count[0x211], 10) << step;
    EXPECT_EQ(count[0x221], 50) << step;
    EXPECT_EQ(count[0x311], 50) << step;
    for (std::uint32_t m = 0; m < 4; ++m) {
      EXPECT_EQ(count[0x251 + m], 50) << step;
      EXPECT_EQ(count[0x261 + m], 50) << step;
    }
    EXPECT_EQ(count[0x361], 2) << step;
    EXPECT_EQ(count.size(), 12u);
  }
}

TEST(ScoutFirmware, IntegratesThePoseOnExactArcsAndReportsWheelTravel) {
  FirmwareParams p;
  ScoutMiniFirmware fw(p, PlanarPose{1.0, -2.0, 0.5});
  fw.receive(encode_control_mode(ControlMode::can), 0.0);
  drive(fw, 0.0, 2.0, motion(0.5, 0.4));  // steady by now
  ASSERT_DOUBLE_EQ(fw.v_mps(), 0.5);
  ASSERT_DOUBLE_EQ(fw.omega_radps(), 0.4);
  const PlanarPose a = fw.pose();
  const double left0 = fw.wheel_left_m();
  const double right0 = fw.wheel_right_m();
  std::vector<CanFrame> out;
  drive(fw, 2.0, 5.0, motion(0.5, 0.4), &out);
  const double T = 3.0;
  const double R = 0.5 / 0.4;
  const double yaw1 = a.yaw_rad + 0.4 * T;
  EXPECT_NEAR(fw.pose().x_m, a.x_m + R * (std::sin(yaw1) - std::sin(a.yaw_rad)), 1e-9);
  EXPECT_NEAR(fw.pose().y_m, a.y_m - R * (std::cos(yaw1) - std::cos(a.yaw_rad)), 1e-9);
  EXPECT_NEAR(std::remainder(fw.pose().yaw_rad - yaw1, 2 * M_PI), 0.0, 1e-9);
  EXPECT_NEAR(fw.wheel_left_m() - left0, (0.5 - 0.4 * p.track_width_m / 2) * T, 1e-9);
  EXPECT_NEAR(fw.wheel_right_m() - right0, (0.5 + 0.4 * p.track_width_m / 2) * T, 1e-9);
  // The last 0x311 reports the travel in mm; 0x221 the speeds; right-side motors spin faster.
  Odometry odo;
  MotionState ms;
  std::map<int, double> rpm;
  for (const CanFrame& f : out) {
    if (f.id == id::kOdometry) decode_odometry(f, odo);
    if (f.id == id::kMotionState) decode_motion_state(f, ms);
    ActuatorHighSpeed hs;
    if (decode_actuator_high_speed(f, hs) == DecodeStatus::ok) rpm[hs.motor] = hs.speed_rpm;
  }
  EXPECT_EQ(odo.left_mm, std::lround(fw.wheel_left_m() * 1000));
  EXPECT_EQ(odo.right_mm, std::lround(fw.wheel_right_m() * 1000));
  EXPECT_DOUBLE_EQ(ms.v_mps, 0.5);
  EXPECT_DOUBLE_EQ(ms.omega_radps, 0.4);
  const double right_rpm = (0.5 + 0.4 * p.track_width_m / 2) / p.wheel_radius_m * 60 / (2 * M_PI);
  EXPECT_EQ(rpm[0], std::lround(right_rpm));
  EXPECT_EQ(rpm[3], std::lround(right_rpm));
  EXPECT_LT(rpm[1], rpm[0]);
}

TEST(ScoutFirmware, FaultsStopTheBaseUntilClearedOverCan) {
  ScoutMiniFirmware fw;
  fw.receive(encode_control_mode(ControlMode::can), 0.0);
  drive(fw, 0.0, 1.0, motion(0.5, 0.0));
  EXPECT_TRUE(fw.raise_error(error_bit::kBatteryUnderVoltageWarning));
  drive(fw, 1.0, 1.2, motion(0.5, 0.0));
  EXPECT_EQ(fw.vehicle_state(), VehicleState::normal);  // a warning does not stop
  EXPECT_DOUBLE_EQ(fw.v_mps(), 0.5);
  EXPECT_TRUE(fw.raise_error(error_bit::kMotor3Comm));
  std::vector<CanFrame> out;
  drive(fw, 1.2, 2.5, motion(0.5, 0.0), &out);
  EXPECT_EQ(fw.vehicle_state(), VehicleState::exception);
  EXPECT_EQ(fw.v_mps(), 0.0);
  const SystemState st = last_system_state(out);
  EXPECT_EQ(st.vehicle_state, 2);
  EXPECT_EQ(st.error_bits, error_bit::kMotor3Comm | error_bit::kBatteryUnderVoltageWarning);
  fw.receive(encode_error_clear(3), 2.5);  // clears motor 3 only
  drive(fw, 2.5, 3.5, motion(0.5, 0.0));
  EXPECT_EQ(fw.errors(), error_bit::kBatteryUnderVoltageWarning);
  EXPECT_DOUBLE_EQ(fw.v_mps(), 0.5);
  fw.set_estop_button(true);
  drive(fw, 3.5, 4.5, motion(0.5, 0.0));
  EXPECT_EQ(fw.vehicle_state(), VehicleState::estop);
  EXPECT_EQ(fw.v_mps(), 0.0);
  EXPECT_FALSE(fw.raise_error(0x10000));
  EXPECT_TRUE(fw.clear_errors());
  EXPECT_EQ(fw.errors(), 0);
}

TEST(ScoutFirmware, PowerCycleSilencesThenBootsInStandbyWithCountersReset) {
  ScoutMiniFirmware fw;
  fw.receive(encode_control_mode(ControlMode::can), 0.0);
  drive(fw, 0.0, 1.0, motion(0.5, 0.0));
  const PlanarPose before = fw.pose();
  ASSERT_TRUE(fw.power_cycle(1.0, 0.3));
  std::vector<CanFrame> out;
  drive(fw, 1.0, 1.299, motion(0.5, 0.0), &out);
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(fw.powered());
  EXPECT_EQ(fw.pose().x_m, before.x_m);  // power cut: the body stops where it is
  drive(fw, 1.299, 2.0, motion(0.5, 0.0), &out);
  EXPECT_TRUE(fw.powered());
  EXPECT_EQ(fw.mode(), ControlMode::standby);
  EXPECT_EQ(fw.v_mps(), 0.0);
  ASSERT_FALSE(out.empty());
  EXPECT_EQ(out.front().utime, 1320000);  // first frame one period after power-on
  Odometry odo;
  for (const CanFrame& f : out) {
    if (f.id == id::kOdometry) decode_odometry(f, odo);
  }
  EXPECT_EQ(odo.left_mm, 0);
  EXPECT_EQ(last_system_state(out).control_mode, 0);
}

TEST(ScoutFirmware, StreamsCanBeStoppedOneByOne) {
  ScoutMiniFirmware fw;
  EXPECT_TRUE(fw.set_stream_enabled(0x221, false));
  EXPECT_TRUE(fw.set_stream_enabled(0x252, false));
  EXPECT_FALSE(fw.set_stream_enabled(0x111, false));
  std::vector<CanFrame> out;
  idle(fw, 1.0, &out);
  std::map<std::uint32_t, int> count;
  for (const CanFrame& f : out) ++count[f.id];
  EXPECT_EQ(count[0x221], 0);
  EXPECT_EQ(count[0x252], 0);
  EXPECT_EQ(count[0x251], 50);
  EXPECT_EQ(count[0x211], 10);
  EXPECT_TRUE(fw.set_stream_enabled(0x221, true));
  out.clear();
  idle(fw, 1.1, &out);
  count.clear();
  for (const CanFrame& f : out) ++count[f.id];
  EXPECT_EQ(count[0x221], 5);
}

TEST(ScoutFirmware, AFloodOfFramesIsBounded) {
  FirmwareParams p;
  p.input_queue_capacity = 1000;
  ScoutMiniFirmware fw(p);
  CanFrame junk;
  junk.id = 0x7AB;
  junk.dlc = 8;
  for (int i = 0; i < 100000; ++i) fw.receive(junk, 0.5);
  EXPECT_EQ(fw.frames_dropped(), 99000u);
  fw.receive(encode_control_mode(ControlMode::can), 0.6);
  idle(fw, 1.0);
  EXPECT_EQ(fw.mode(), ControlMode::can);
  EXPECT_EQ(fw.frames_ignored(), 999u);
}

}  // namespace
}  // namespace porter::scout_mini
