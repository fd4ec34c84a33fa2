// Fuzz target: the Piper driver logic fed arbitrary frames at arbitrary times, stepped at
// 200 Hz. Whatever arrives: no crash, bounded events, targets only while active and within
// the joint limits when they come from a command, shutdown always finishes.
#include <cmath>
#include <cstdint>
#include <vector>

#include "piper_fuzz_input.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/piper/protocol.hpp"

using namespace porter::piper;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ArmDriverParams params;
  params.lower_rad = {-2.6179, 0.0, -2.967, -1.745, -1.22, -2.09439};
  params.upper_rad = {2.6179, 3.14, 0.0, 1.745, 1.22, 2.09439};
  ArmDriver driver(params);
  ArmCommand cmd;
  cmd.q_rad = {5.0, -5.0, 5.0, -5.0, 5.0, -5.0};  // far outside every limit: must be clamped
  std::vector<porter::can::CanFrame> out;
  double t = 0.0;
  double next_step = 0.005;
  auto step_until = [&](double until) {
    while (next_step <= until) {
      out.clear();
      driver.step(next_step, out);
      for (const porter::can::CanFrame& f : out) {
        if (!f.valid()) __builtin_trap();
        if (f.id >= id::kJointCtrl12 && f.id <= id::kJointCtrl56 && driver.phase() != ArmPhase::active) {
          __builtin_trap();
        }
      }
      if (driver.phase() == ArmPhase::active && !driver.status(next_step).holding) {
        for (int j = 0; j < kNumJoints; ++j) {
          const double q = driver.last_targets()[j];
          if (q < params.lower_rad[j] || q > params.upper_rad[j]) __builtin_trap();
        }
      }
      next_step += 0.005;
    }
  };
  for (std::size_t at = 0; at + fuzz::kRecordSize <= size; at += fuzz::kRecordSize) {
    const fuzz::Record r = fuzz::record_at(data + at);
    t += (r.advance_ms % 64) * 1e-3;  // up to 63 ms: a few records cross every timeout
    step_until(t);
    driver.on_frame(r.frame, t);
    if (r.frame.data[0] == 0xC3) driver.on_command(cmd, t);
    if (r.frame.data[0] == 0xE5) driver.on_estop(r.frame.data[1] & 1, "fuzz", t);
  }
  if (driver.take_events().size() > 256) __builtin_trap();
  driver.request_shutdown("fuzz", t);
  step_until(t + params.shutdown_timeout_s + 0.1);
  if (!driver.finished()) __builtin_trap();
  return 0;
}
