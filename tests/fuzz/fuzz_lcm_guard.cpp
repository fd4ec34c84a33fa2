// Fuzz target: the LCM guard of one message type (PORTER_FUZZ_LCM_TYPE, set per binary by
// tests/fuzz/lcm.cmake). Input: a mode byte, then the datagram. Mode bit 0 clear: the type's
// fingerprint is put in front of the rest (so mutations explore the members, not the hash);
// set: the rest is the whole datagram. Whatever the guard accepts must decode with lcm-gen's
// decoder to exactly its size and encode again; anything else aborts.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "porter/lcm_guard.hpp"

#define PORTER_STR2(x) #x
#define PORTER_STR(x) PORTER_STR2(x)
#include PORTER_STR(porter/PORTER_FUZZ_LCM_TYPE.hpp)

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using T = porter::PORTER_FUZZ_LCM_TYPE;
  if (size < 1) return 0;
  std::vector<std::uint8_t> datagram;
  if ((data[0] & 1u) == 0) {
    const auto hash = static_cast<std::uint64_t>(T::getHash());
    for (int i = 7; i >= 0; --i) datagram.push_back(static_cast<std::uint8_t>(hash >> (8 * i)));
  }
  datagram.insert(datagram.end(), data + 1, data + size);
  const porter::LcmGuardResult guard = porter::lcm_guard_check<T>(datagram.data(), datagram.size());
  if (!guard.ok) {
    if (guard.describe().empty()) std::abort();
    return 0;
  }
  T msg;
  const int n = static_cast<int>(datagram.size());
  if (msg.decode(datagram.data(), 0, n) != n) std::abort();  // the guard let through a bad datagram
  const int encoded_size = msg.getEncodedSize();
  if (encoded_size < 8) std::abort();
  std::vector<std::uint8_t> again(static_cast<std::size_t>(encoded_size));
  msg.encode(again.data(), 0, encoded_size);  // strings with a NUL inside encode shorter: no check
  return 0;
}
