// Fuzz target: the Scout Mini firmware model (what porter-sim hosts) on any sequence of frames
// from the bus. Checks: no crash or out-of-bounds read; the body's speeds stay within the
// firmware's limits and the pose finite; every frame it sends is valid.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "porter/scout_mini/firmware.hpp"
#include "scout_mini_frames.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace porter::scout_mini;
  FirmwareParams params;
  params.input_queue_capacity = 64;
  ScoutMiniFirmware fw(params);
  std::vector<porter::can::CanFrame> out;
  for (const porter::fuzz::TimedFrame& tf : porter::fuzz::scout_mini_frames(data, size)) {
    fw.receive(tf.frame, tf.t_s);
    out.clear();
    fw.advance(tf.t_s, out);
    for (const porter::can::CanFrame& f : out) {
      if (!f.valid()) std::abort();
    }
    if (std::abs(fw.v_mps()) > params.v_max_mps + 1e-9 ||
        std::abs(fw.omega_radps()) > params.omega_max_radps + 1e-9 ||
        !std::isfinite(fw.pose().x_m) || !std::isfinite(fw.pose().yaw_rad)) {
      std::abort();
    }
  }
  return 0;
}
