// Fuzz target: the candump-style text form of a frame built from arbitrary bytes (checks
// to_string never reads past the frame whatever its dlc says).
#include <cstdint>
#include <cstring>

#include "porter/can/can_frame.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  porter::can::CanFrame frame;
  if (size < 6) return 0;
  std::memcpy(&frame.id, data, 4);
  frame.dlc = data[4];
  frame.extended = (data[5] & 1) != 0;
  frame.rtr = (data[5] & 2) != 0;
  for (std::size_t i = 0; i < 8 && 6 + i < size; ++i) frame.data[i] = data[6 + i];
  const std::string text = porter::can::to_string(frame);
  return text.empty() ? 1 : 0;
}
