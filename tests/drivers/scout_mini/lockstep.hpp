#pragma once
// The driver's logic and the firmware model on one simulated clock (1 ms steps), joined by a
// perfect bus that tests can cut. Frames each side sent are logged with their time.

#include <cmath>
#include <functional>
#include <vector>

#include "porter/scout_mini/base_driver.hpp"
#include "porter/scout_mini/firmware.hpp"

namespace porter::scout_mini::test {

struct TimedFrame {
  double t_s;
  CanFrame frame;
};

struct Lockstep {
  explicit Lockstep(DriverParams driver_params = {}, FirmwareParams firmware_params = {})
      : params(driver_params), driver(driver_params), firmware(firmware_params) {}

  /// Runs until t_end_s; `each_ms` runs first in every step (commands, faults).
  void run_until(double t_end_s, const std::function<void(double)>& each_ms = {}) {
    while (now() < t_end_s - 1e-9) {
      ++ms;
      const double t = now();
      if (each_ms) each_ms(t);
      std::vector<CanFrame> out;
      firmware.advance(t, out);
      for (const CanFrame& f : out) {
        from_firmware.push_back({t, f});
        if (bus_up) driver.on_frame(f, t);
      }
      if (ms % tick_ms == 0) {
        std::vector<CanFrame> cmds;
        driver.tick(t, cmds);
        for (const CanFrame& f : cmds) {
          from_driver.push_back({t, f});
          if (bus_up) firmware.receive(f, t);
        }
      }
    }
  }

  double now() const { return ms * 1e-3; }

  /// Times of the 0x111 frames the driver sent after t0 whose velocity was zero.
  double first_zero_command_after(double t0) const {
    for (const TimedFrame& tf : from_driver) {
      MotionCommand c;
      if (tf.t_s > t0 && decode_motion_command(tf.frame, c) == DecodeStatus::ok &&
          c.v_mps == 0.0 && c.omega_radps == 0.0) {
        return tf.t_s;
      }
    }
    return -1.0;
  }

  DriverParams params;
  BaseDriver driver;
  ScoutMiniFirmware firmware;
  long ms = 0;
  long tick_ms = 20;
  bool bus_up = true;
  std::vector<TimedFrame> from_driver;
  std::vector<TimedFrame> from_firmware;
};

}  // namespace porter::scout_mini::test
