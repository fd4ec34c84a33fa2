#pragma once
// Input format shared by the Piper fuzz targets: a sequence of 12-byte records, each a time
// step and one CAN frame exactly as a bus could deliver it (any ID, any dlc up to 15, extended
// and RTR flags):
//   [0]     milliseconds to advance before the frame (targets that keep time)
//   [1..2]  ID, big-endian (masked to 11 bits unless extended)
//   [3]     bits 0-3 dlc (0..15; > 8 is an invalid frame), bit 4 extended, bit 5 RTR
//   [4..11] data bytes
// A trailing partial record is ignored.

#include <cstddef>
#include <cstdint>

#include "porter/can/can_frame.hpp"

namespace porter::piper::fuzz {

inline constexpr std::size_t kRecordSize = 12;

struct Record {
  int advance_ms = 0;
  can::CanFrame frame;
};

inline Record record_at(const std::uint8_t* p) {
  Record r;
  r.advance_ms = p[0];
  r.frame.extended = (p[3] & 0x10) != 0;
  r.frame.rtr = (p[3] & 0x20) != 0;
  const std::uint32_t id = (static_cast<std::uint32_t>(p[1]) << 8) | p[2];
  r.frame.id = r.frame.extended ? id : (id & 0x7FF);
  r.frame.dlc = p[3] & 0x0F;
  for (int i = 0; i < 8; ++i) r.frame.data[i] = p[4 + i];
  return r;
}

}  // namespace porter::piper::fuzz
