// Fuzz target: PiperFirmware fed arbitrary frames at arbitrary times. Whatever arrives, the
// joints stay finite and within the firmware's limits, and every frame it sends is valid.
#include <cmath>
#include <cstdint>
#include <vector>

#include "piper_fuzz_input.hpp"
#include "porter/piper/piper_firmware.hpp"

using namespace porter::piper;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const PiperFirmwareParams params;
  PiperFirmware fw(params);
  std::vector<porter::can::CanFrame> out;
  double t = 0.0;
  for (std::size_t at = 0; at + fuzz::kRecordSize <= size; at += fuzz::kRecordSize) {
    const fuzz::Record r = fuzz::record_at(data + at);
    t += (r.advance_ms % 64) * 1e-3;  // up to 63 ms: enough to cross every feedback period
    out.clear();
    fw.advance(t, out);
    for (const porter::can::CanFrame& f : out) {
      if (!f.valid() || f.dlc != 8) __builtin_trap();
    }
    if (r.frame.data[7] == 0xA5 && r.frame.data[6] == 0x5A) fw.power_cycle();  // reachable by mutation
    fw.receive(r.frame, t);
    const PiperTruth& truth = fw.truth();
    for (int j = 0; j < kNumJoints; ++j) {
      if (!std::isfinite(truth.q_rad[j]) || !std::isfinite(truth.qd_radps[j])) __builtin_trap();
      if (truth.q_rad[j] < params.lower_rad[j] - 1e-9 || truth.q_rad[j] > params.upper_rad[j] + 1e-9) {
        __builtin_trap();
      }
      if (std::abs(truth.qd_radps[j]) > params.max_speed_radps[j] + 1e-9) __builtin_trap();
    }
    if (truth.gripper_m < 0.0 || truth.gripper_m > params.gripper_max_m) __builtin_trap();
  }
  return 0;
}
