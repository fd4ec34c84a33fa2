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

namespace {
using T = porter::PORTER_FUZZ_LCM_TYPE;

// The fingerprint, big-endian, computed once.
struct Fingerprint {
  std::uint8_t bytes[8];
  Fingerprint() {
    const auto hash = static_cast<std::uint64_t>(T::getHash());
    for (int i = 0; i < 8; ++i) bytes[i] = static_cast<std::uint8_t>(hash >> (8 * (7 - i)));
  }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const Fingerprint fingerprint;
  if (size < 1) return 0;
  // One block of exactly the datagram's size per input (not a reused buffer): a read past its
  // end is then a heap-buffer-overflow that ASan reports.
  const std::size_t prefix = (data[0] & 1u) == 0 ? 8 : 0;
  const std::size_t length = prefix + size - 1;
  std::vector<std::uint8_t> datagram(length);
  if (prefix != 0) std::memcpy(datagram.data(), fingerprint.bytes, 8);
  if (size > 1) std::memcpy(datagram.data() + prefix, data + 1, size - 1);
  const porter::LcmGuardResult guard = porter::lcm_guard_check<T>(datagram.data(), datagram.size());
  if (!guard.ok) {
    if (*guard.problem == '\0') std::abort();  // every refusal says why
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
