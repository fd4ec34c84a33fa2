// Fuzz target: the SLCAN adapter byte stream (SlcanDecoder, slcan_protocol.hpp), fed in pieces
// whose sizes the input chooses, as a tty delivers them. Checks: no crash or out-of-bounds read,
// bounded line buffer, every decoded frame valid and re-encodable to a line that decodes to the
// same frame.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "porter/can/slcan_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace porter::can;
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 32;
  slcan::SlcanDecoder decoder;
  std::vector<slcan::Item> items;
  for (std::size_t at = 1; at < size; at += chunk) {
    const std::size_t n = at + chunk <= size ? chunk : size - at;
    decoder.feed(data + at, n, items);
    if (decoder.pending() > slcan::kMaxLineLength) std::abort();
  }
  for (const slcan::Item& item : items) {
    if (item.kind != slcan::ItemKind::frame) continue;
    if (!item.frame.valid()) std::abort();
    std::string line = slcan::encode_frame(item.frame);
    if (line.empty() || line.back() != '\r') std::abort();
    line.pop_back();
    const slcan::Item again = slcan::parse_line(line);
    if (again.kind != slcan::ItemKind::frame || !(again.frame == item.frame)) std::abort();
  }
  return 0;
}
