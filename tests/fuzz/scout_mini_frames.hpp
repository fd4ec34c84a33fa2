#pragma once
// Turns fuzz input into a sequence of timed CAN frames for the Scout Mini targets. Each record
// is 12 bytes: flags (bit0 extended, bit1 remote, bit2 pick the ID from the Scout Mini's IDs,
// bits 4-7 milliseconds since the previous frame), two ID bytes, the DLC byte as sent (may
// exceed 8) and eight data bytes (missing bytes at the end of the input are zero).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/can/can_frame.hpp"

namespace porter::fuzz {

struct TimedFrame {
  double t_s;
  can::CanFrame frame;
};

inline std::vector<TimedFrame> scout_mini_frames(const std::uint8_t* data, std::size_t size) {
  static const std::uint32_t kIds[] = {0x111, 0x151, 0x211, 0x221, 0x241, 0x251, 0x252, 0x253,
                                       0x254, 0x261, 0x262, 0x263, 0x264, 0x311, 0x361, 0x421,
                                       0x441};
  std::vector<TimedFrame> out;
  double t = 0.0;
  for (std::size_t at = 0; at < size; at += 12) {
    std::uint8_t r[12] = {0};
    for (std::size_t i = 0; i < 12 && at + i < size; ++i) r[i] = data[at + i];
    can::CanFrame f;
    f.extended = (r[0] & 1) != 0;
    f.rtr = (r[0] & 2) != 0;
    const std::uint32_t raw_id = (static_cast<std::uint32_t>(r[1]) << 8) | r[2];
    f.id = (r[0] & 4) ? kIds[raw_id % (sizeof kIds / sizeof kIds[0])]
                      : (f.extended ? raw_id << 13 : raw_id & 0x7FF);
    f.dlc = r[3];
    for (int i = 0; i < 8; ++i) f.data[i] = r[4 + i];
    t += (r[0] >> 4) * 1e-3;
    out.push_back({t, f});
  }
  return out;
}

}  // namespace porter::fuzz
