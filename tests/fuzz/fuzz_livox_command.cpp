// Fuzz target: a datagram on the MID-360 command channel (porter-lidar reads the sensor's ACKs,
// the simulated sensor reads requests). Decodes the frame, its key-value list and the values
// porter reads, and re-encodes what decoded: the round trip must give the same bytes.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "porter/livox/command.hpp"

using namespace porter::livox;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<std::uint8_t> datagram(data, data + size);  // exact size: no slack to read
  CommandFrame f;
  if (decode_command(datagram.data(), datagram.size(), f) != CommandStatus::ok) return 0;
  // Reserved bytes are not kept: compare with them cleared.
  std::vector<std::uint8_t> expected = datagram;
  for (int i = 12; i < 18; ++i) expected[i] = 0;
  std::vector<std::uint8_t> again = encode_command(f);
  if (again.size() != expected.size()) std::abort();
  for (std::size_t i = 0; i < again.size(); ++i) {
    if (i >= 18 && i < 20) continue;  // the header CRC covers the reserved bytes
    if (again[i] != expected[i]) std::abort();
  }
  std::vector<KeyValue> keys;
  if (decode_key_values(f.data, keys)) {
    if (encode_key_values(keys) != f.data) std::abort();
    for (const KeyValue& kv : keys) {
      StreamDestination d;
      if (read_destination(kv, d) && destination_key(static_cast<ConfigKey>(kv.key), d).value != kv.value) std::abort();
    }
  }
  std::uint8_t ret = 0;
  std::uint16_t key = 0;
  (void)read_config_ack(f.data, ret, key);
  return 0;
}
