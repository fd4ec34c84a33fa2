// Fuzz target: every Scout Mini feedback decoder and the driver's logic (BaseDriver) on any
// sequence of frames, as porter-base's receive thread hands them over, with the 50 Hz tick in
// between. Checks: no crash or out-of-bounds read; what the driver sends stays valid, finite and
// within its limits; its event queue stays bounded.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "porter/scout_mini/base_driver.hpp"
#include "porter/scout_mini/protocol.hpp"
#include "scout_mini_frames.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace porter::scout_mini;
  DriverParams params;
  BaseDriver driver(params);
  driver.on_command(VelocityCommand{true, 0.8, 2.0}, 0.0);
  std::vector<porter::can::CanFrame> out;
  double next_tick = 0.02;
  for (const porter::fuzz::TimedFrame& tf : porter::fuzz::scout_mini_frames(data, size)) {
    // Every decoder on every frame: each must refuse what is not its own.
    MotionCommand mc;
    SystemState ss;
    MotionState ms;
    ActuatorHighSpeed hs;
    ActuatorLowSpeed ls;
    Odometry odo;
    BmsBasic bms;
    std::uint8_t raw = 0;
    decode_motion_command(tf.frame, mc);
    decode_system_state(tf.frame, ss);
    decode_motion_state(tf.frame, ms);
    if (decode_actuator_high_speed(tf.frame, hs) == DecodeStatus::ok && (hs.motor < 0 || hs.motor > 3)) {
      std::abort();
    }
    if (decode_actuator_low_speed(tf.frame, ls) == DecodeStatus::ok && (ls.motor < 0 || ls.motor > 3)) {
      std::abort();
    }
    decode_odometry(tf.frame, odo);
    decode_bms_basic(tf.frame, bms);
    decode_control_mode(tf.frame, raw);
    decode_error_clear(tf.frame, raw);
    error_names(ss.error_bits);
    driver.on_frame(tf.frame, tf.t_s);
    while (next_tick <= tf.t_s) {
      out.clear();
      driver.tick(next_tick, out);
      driver.on_command(VelocityCommand{true, 0.8, 2.0}, next_tick);
      for (const porter::can::CanFrame& f : out) {
        if (!f.valid()) std::abort();
      }
      const VelocityCommand& sent = driver.last_sent();
      if (!std::isfinite(sent.v_mps) || std::abs(sent.v_mps) > params.v_max_mps + 1e-9 ||
          std::abs(sent.omega_radps) > params.omega_max_radps + 1e-9) {
        std::abort();
      }
      next_tick += params.command_period_s;
    }
    const BaseFeedback& fb = driver.feedback();
    if (!std::isfinite(fb.odom_x_m) || !std::isfinite(fb.odom_yaw_rad)) std::abort();
  }
  if (driver.take_events().size() > 256) std::abort();
  return 0;
}
