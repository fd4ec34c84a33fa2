// Fuzz target: SocketCAN controller error frames (decode_error_frame, can_error.hpp) with any
// class bits, any DLC (also above 8) and any data. Checks: no crash or out-of-bounds read, a
// sentence for every report, counters only when the frame says it carries them.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "porter/can/can_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace porter::can;
  if (size < 5) return 0;
  CanFrame frame;
  std::uint32_t id = 0;
  std::memcpy(&id, data, 4);
  frame.id = id;
  frame.extended = true;
  frame.dlc = data[4];
  for (std::size_t i = 0; i < 8 && 5 + i < size; ++i) frame.data[i] = data[5 + i];
  const ControllerError e = decode_error_frame(frame);
  if (e.text.empty()) std::abort();
  if ((e.tx_error_count >= 0) != ((e.classes & 0x200u) != 0)) std::abort();
  return 0;
}
