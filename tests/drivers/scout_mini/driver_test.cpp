// The driver's logic against the firmware model on one simulated clock: enable sequence,
// command streaming and limits, stale-command stop, e-stop latch and release, re-enable after a
// power cycle, fault decoding, link loss, protocol V1 refusal, odometry.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "lockstep.hpp"

namespace porter::scout_mini {
namespace {

using test::Lockstep;

VelocityCommand cmd(double v, double w) { return VelocityCommand{true, v, w}; }

bool has_event(const std::vector<DriverEvent>& events, const std::string& text) {
  for (const DriverEvent& e : events) {
    if (e.message.find(text) != std::string::npos) return true;
  }
  return false;
}

// Streams `c` at 100 Hz (as porter-tracker does) during the run.
std::function<void(double)> stream(Lockstep& ls, VelocityCommand c, double until_s = 1e9) {
  return [&ls, c, until_s](double t) {
    const long k = std::lround(t * 1000);
    if (k % 10 == 0 && t <= until_s + 1e-9) ls.driver.on_command(c, t);
  };
}

TEST(BaseDriverTest, EntersCommandModeThenStopsAsking) {
  Lockstep ls;
  ls.run_until(1.0);
  EXPECT_EQ(ls.firmware.mode(), ControlMode::can);
  EXPECT_EQ(ls.driver.feedback().control_mode, 1);
  int mode_frames = 0;
  double last_mode_t = 0;
  for (const auto& tf : ls.from_driver) {
    if (tf.frame.id == id::kControlMode) {
      ++mode_frames;
      last_mode_t = tf.t_s;
    }
  }
  // Sent at the first tick and until the first 0x211 (at 100 ms) shows CAN mode.
  EXPECT_GE(mode_frames, 1);
  EXPECT_LE(mode_frames, 3);
  EXPECT_LE(last_mode_t, 0.2);
  EXPECT_TRUE(ls.driver.feedback().link_ok);
  EXPECT_EQ(ls.driver.problem(), "");
  const auto events = ls.driver.take_events();
  // The 0x421 of the first tick reaches the base before its first 0x211 (at 100 ms).
  EXPECT_TRUE(has_event(events, "base in CAN command mode (was unknown)"));
  // 0x111 at 50 Hz from the first tick.
  int motion_frames = 0;
  for (const auto& tf : ls.from_driver) motion_frames += tf.frame.id == id::kMotionCommand;
  EXPECT_EQ(motion_frames, 50);
}

TEST(BaseDriverTest, StreamsCommandsAndTracksTheBaseWithOdometry) {
  Lockstep ls;
  ls.run_until(6.0, stream(ls, cmd(0.5, 0.3)));
  EXPECT_DOUBLE_EQ(ls.firmware.v_mps(), 0.5);
  EXPECT_DOUBLE_EQ(ls.firmware.omega_radps(), 0.3);
  const BaseFeedback& fb = ls.driver.feedback();
  EXPECT_DOUBLE_EQ(fb.v_mps, 0.5);
  EXPECT_DOUBLE_EQ(fb.omega_radps, 0.3);
  EXPECT_FALSE(fb.cmd_stale);
  // Odometry from the 0x311 millimetres against the firmware's own pose (started at 0).
  EXPECT_NEAR(fb.odom_x_m, ls.firmware.pose().x_m, 0.01);
  EXPECT_NEAR(fb.odom_y_m, ls.firmware.pose().y_m, 0.01);
  EXPECT_NEAR(std::remainder(fb.odom_yaw_rad - ls.firmware.pose().yaw_rad, 2 * M_PI), 0.0, 0.01);
  EXPECT_NEAR(fb.wheel_right_m, ls.firmware.wheel_right_m(), 0.002);
  EXPECT_GT(fb.motor_speed_rpm[0], fb.motor_speed_rpm[1]);
  EXPECT_DOUBLE_EQ(fb.battery_soc_pct, 90.0);
  EXPECT_DOUBLE_EQ(fb.battery_voltage_v, 25.2);
  EXPECT_EQ(fb.feedback_utime, 6000000);
  EXPECT_EQ(ls.driver.frames_malformed(), 0u);
  EXPECT_EQ(ls.driver.frames_unknown(), 0u);
}

TEST(BaseDriverTest, LimitsKeepCurvatureAndWheelSpeeds) {
  DriverParams p;
  bool limited = false;
  VelocityCommand out = limit_command(cmd(2.0, 1.0), p, &limited);
  EXPECT_TRUE(limited);
  EXPECT_DOUBLE_EQ(out.omega_radps / out.v_mps, 0.5);
  const double wheel = p.wheel_omega_max_radps * p.wheel_radius_m;  // 1.05 m/s
  EXPECT_LE(out.v_mps + out.omega_radps * p.track_width_m / 2, wheel + 1e-12);
  EXPECT_LE(out.v_mps, p.v_max_mps);
  out = limit_command(cmd(0.0, 9.0), p, &limited);  // turning on the spot: yaw-rate limit
  EXPECT_DOUBLE_EQ(out.omega_radps, p.omega_max_radps);
  DriverParams wide = p;
  wide.omega_max_radps = 10.0;
  out = limit_command(cmd(0.0, 9.0), wide, &limited);  // now the wheel limit binds
  EXPECT_NEAR(out.omega_radps, wheel / (p.track_width_m / 2), 1e-12);
  out = limit_command(cmd(-0.3, 0.2), p, &limited);
  EXPECT_FALSE(limited);
  EXPECT_EQ(out.v_mps, -0.3);
  out = limit_command(cmd(std::numeric_limits<double>::quiet_NaN(), 0.2), p, &limited);
  EXPECT_TRUE(limited);
  EXPECT_EQ(out.v_mps, 0.0);
  EXPECT_EQ(out.omega_radps, 0.0);
  // Through the driver: the base receives the limited command.
  Lockstep ls;
  ls.run_until(3.0, stream(ls, cmd(3.0, 0.0)));
  EXPECT_NEAR(ls.firmware.v_mps(), p.v_max_mps, 1e-9);
  EXPECT_TRUE(has_event(ls.driver.take_events(), "limited"));
}

TEST(BaseDriverTest, StaleCommandsStopTheBaseWithinTheLimit) {
  Lockstep ls;
  const double last_cmd_t = 2.0;
  ls.run_until(4.0, stream(ls, cmd(0.4, 0.0), last_cmd_t));
  // While commands streamed, no zero went out once the base was moving.
  EXPECT_EQ(ls.first_zero_command_after(0.1), ls.first_zero_command_after(last_cmd_t));
  const double zero_t = ls.first_zero_command_after(last_cmd_t);
  ASSERT_GT(zero_t, 0);
  EXPECT_LE(zero_t - last_cmd_t, ls.params.command_stale_s + 1e-9);
  EXPECT_GT(zero_t - last_cmd_t, ls.params.command_stale_s - ls.params.command_period_s);
  EXPECT_TRUE(ls.driver.feedback().cmd_stale);
  EXPECT_EQ(ls.firmware.v_mps(), 0.0);
  EXPECT_TRUE(has_event(ls.driver.take_events(), "BASE_CMD stale"));
  // A disabled command is a stop too.
  Lockstep off;
  off.run_until(2.0, stream(off, VelocityCommand{false, 0.4, 0.0}));
  EXPECT_EQ(off.firmware.v_mps(), 0.0);
}

TEST(BaseDriverTest, EstopLatchesUntilReleaseAndANewCommand) {
  Lockstep ls;
  ls.run_until(1.5, stream(ls, cmd(0.3, 0.0)));
  ASSERT_DOUBLE_EQ(ls.firmware.v_mps(), 0.3);
  ls.driver.on_estop(true, "operator: test", ls.now());
  const double estop_t = ls.now();
  ls.run_until(3.0, stream(ls, cmd(0.3, 0.0)));
  const double zero_t = ls.first_zero_command_after(estop_t);
  EXPECT_LE(zero_t - estop_t, ls.params.command_period_s + 1e-9);
  EXPECT_EQ(ls.firmware.v_mps(), 0.0);
  EXPECT_TRUE(ls.driver.feedback().estop_active);
  EXPECT_EQ(ls.driver.problem(), "ESTOP engaged");
  // Repeating the active state changes nothing; the release alone does not move the base.
  ls.driver.on_estop(true, "operator: repeat", ls.now());
  ls.driver.on_estop(false, "operator: release", ls.now());
  ls.run_until(3.5);
  EXPECT_EQ(ls.firmware.v_mps(), 0.0);
  EXPECT_FALSE(ls.driver.feedback().estop_active);
  ls.run_until(5.0, stream(ls, cmd(0.3, 0.0)));
  EXPECT_DOUBLE_EQ(ls.firmware.v_mps(), 0.3);
  const auto events = ls.driver.take_events();
  EXPECT_TRUE(has_event(events, "ESTOP engaged (operator: test)"));
  EXPECT_TRUE(has_event(events, "ESTOP released (operator: release)"));
}

TEST(BaseDriverTest, ReEnablesAfterAPowerCycleAndKeepsOdometryContinuous) {
  Lockstep ls;
  ls.run_until(2.0, stream(ls, cmd(0.3, 0.0)));
  ASSERT_DOUBLE_EQ(ls.firmware.v_mps(), 0.3);
  const double x_before = ls.driver.feedback().odom_x_m;
  ls.firmware.power_cycle(ls.now(), 0.5);
  ls.run_until(4.0, stream(ls, cmd(0.3, 0.0)));
  EXPECT_EQ(ls.firmware.mode(), ControlMode::can);
  EXPECT_DOUBLE_EQ(ls.firmware.v_mps(), 0.3);
  const auto events = ls.driver.take_events();
  EXPECT_TRUE(has_event(events, "CAN feedback lost"));
  EXPECT_TRUE(has_event(events, "CAN feedback restored"));
  // While the link was down the driver kept sending 0x421, so the base may be in CAN mode
  // before its first report after power-on.
  EXPECT_TRUE(has_event(events, "base in CAN command mode (was unknown)"));
  EXPECT_TRUE(has_event(events, "counters jumped"));
  // 0x421 went out again after the power-on.
  bool reenabled = false;
  for (const auto& tf : ls.from_driver) reenabled |= tf.frame.id == id::kControlMode && tf.t_s > 2.5;
  EXPECT_TRUE(reenabled);
  // The odometry pose kept going from where it was (no jump back to the counters' zero).
  EXPECT_GT(ls.driver.feedback().odom_x_m, x_before);
  EXPECT_NEAR(ls.driver.feedback().odom_x_m, ls.firmware.pose().x_m, 0.02);
}

TEST(BaseDriverTest, DecodesFaultsAsNames) {
  Lockstep ls;
  ls.run_until(1.0, stream(ls, cmd(0.2, 0.0)));
  ls.firmware.raise_error(error_bit::kMotor2Comm | error_bit::kBatteryUnderVoltageWarning);
  ls.run_until(1.5, stream(ls, cmd(0.2, 0.0)));
  const BaseFeedback& fb = ls.driver.feedback();
  EXPECT_EQ(fb.error_bits, error_bit::kMotor2Comm | error_bit::kBatteryUnderVoltageWarning);
  EXPECT_EQ(fb.vehicle_state, static_cast<int>(VehicleState::exception));
  EXPECT_EQ(ls.driver.problem(), "base vehicle state exception");
  auto events = ls.driver.take_events();
  EXPECT_TRUE(has_event(events, "base errors raised: battery_under_voltage_warning, motor2_comm"));
  EXPECT_TRUE(has_event(events, "base vehicle state exception (was normal)"));
  ls.firmware.clear_errors();
  ls.run_until(2.0, stream(ls, cmd(0.2, 0.0)));
  events = ls.driver.take_events();
  EXPECT_TRUE(has_event(events, "base errors cleared"));
  EXPECT_EQ(ls.driver.problem(), "");
}

TEST(BaseDriverTest, LostFeedbackZeroesTheCommandUntilItReturns) {
  Lockstep ls;
  ls.run_until(1.0, stream(ls, cmd(0.3, 0.0)));
  ls.bus_up = false;
  const double cut_t = ls.now();
  ls.run_until(1.5, stream(ls, cmd(0.3, 0.0)));
  EXPECT_FALSE(ls.driver.feedback().link_ok);
  EXPECT_EQ(ls.driver.last_sent().v_mps, 0.0);
  EXPECT_EQ(ls.driver.problem(), "no CAN feedback from the base");
  bool lost_in_time = false;
  for (const auto& e : ls.driver.take_events()) {
    if (e.message.find("CAN feedback lost") != std::string::npos) {
      lost_in_time = e.t_s - cut_t <= ls.params.feedback_timeout_s + 0.021;
    }
  }
  EXPECT_TRUE(lost_in_time);
  ls.bus_up = true;
  ls.run_until(3.0, stream(ls, cmd(0.3, 0.0)));
  EXPECT_TRUE(ls.driver.feedback().link_ok);
  EXPECT_DOUBLE_EQ(ls.firmware.v_mps(), 0.3);
}

TEST(BaseDriverTest, RefusesAProtocolV1Base) {
  BaseDriver driver{DriverParams{}};
  CanFrame v1;
  v1.id = id::kV1Feedback;
  v1.dlc = 8;
  driver.on_frame(v1, 0.01);
  std::vector<CanFrame> out;
  driver.on_command(cmd(0.3, 0.0), 0.02);
  driver.tick(0.02, out);
  driver.stop_frames(out);
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(driver.refused());
  EXPECT_EQ(driver.problem(), "base speaks protocol V1: refused");
  const auto events = driver.take_events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events[0].level, EventLevel::error);
  EXPECT_NE(events[0].message.find("protocol V1"), std::string::npos);
  // After V2 frames, a stray 0x151 is only a warning.
  Lockstep ls;
  ls.run_until(0.5);
  ls.driver.on_frame(v1, ls.now());
  EXPECT_FALSE(ls.driver.refused());
  EXPECT_TRUE(has_event(ls.driver.take_events(), "V1-only frame"));
}

TEST(BaseDriverTest, ShutdownSendsAZeroCommand) {
  Lockstep ls;
  ls.run_until(1.0, stream(ls, cmd(0.3, 0.0)));
  std::vector<CanFrame> out;
  ls.driver.stop_frames(out);
  ASSERT_EQ(out.size(), 1u);
  MotionCommand c;
  ASSERT_EQ(decode_motion_command(out[0], c), DecodeStatus::ok);
  EXPECT_EQ(c.v_mps, 0.0);
  EXPECT_EQ(c.omega_radps, 0.0);
}

TEST(BaseDriverTest, MalformedAndForeignFramesAreCountedNotTrusted) {
  BaseDriver driver{DriverParams{}};
  CanFrame short_odo;
  short_odo.id = id::kOdometry;
  short_odo.dlc = 3;
  driver.on_frame(short_odo, 0.0);
  CanFrame unknown;
  unknown.id = 0x6FF;
  driver.on_frame(unknown, 0.0);
  CanFrame ext;
  ext.id = id::kMotionState;
  ext.extended = true;
  ext.dlc = 8;
  driver.on_frame(ext, 0.0);
  EXPECT_EQ(driver.frames_malformed(), 1u);
  EXPECT_EQ(driver.frames_unknown(), 2u);
  EXPECT_EQ(driver.frames_decoded(), 0u);
  EXPECT_FALSE(driver.feedback().link_ok);
}

}  // namespace
}  // namespace porter::scout_mini
