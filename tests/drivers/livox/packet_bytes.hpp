#pragma once
// Hand-built MID-360 datagrams for the tests: bytes written field by field from the protocol
// table (not by porter's encoder), and a bitwise CRC-32 as the slow reference.

#include <cstdint>
#include <cstring>
#include <vector>

namespace porter::livox::test {

using Bytes = std::vector<std::uint8_t>;

/// Bit-at-a-time CRC-32 (reflected 0x04C11DB7, init and final xor 0xFFFFFFFF).
inline std::uint32_t crc32_bitwise(const std::uint8_t* data, std::size_t size) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= data[i];
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : (c >> 1);
  }
  return ~c;
}

/// Bit-at-a-time CRC-16/CCITT-FALSE.
inline std::uint16_t crc16_bitwise(const std::uint8_t* data, std::size_t size) {
  std::uint16_t c = 0xFFFF;
  for (std::size_t i = 0; i < size; ++i) {
    c ^= static_cast<std::uint16_t>(data[i] << 8);
    for (int k = 0; k < 8; ++k) c = (c & 0x8000u) ? static_cast<std::uint16_t>((c << 1) ^ 0x1021u) : static_cast<std::uint16_t>(c << 1);
  }
  return c;
}

inline void put_le(Bytes& b, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b.push_back(static_cast<std::uint8_t>((v >> (8 * i)) & 0xFF));
}

/// 36-byte header with the CRC left 0 (finish() fills it).
inline Bytes header(std::uint16_t length, std::uint16_t time_interval, std::uint16_t dot_num,
                    std::uint16_t udp_cnt, std::uint8_t frame_cnt, std::uint8_t data_type,
                    std::uint8_t time_type, std::uint64_t timestamp) {
  Bytes b;
  b.push_back(0);  // version
  put_le(b, length, 2);
  put_le(b, time_interval, 2);
  put_le(b, dot_num, 2);
  put_le(b, udp_cnt, 2);
  b.push_back(frame_cnt);
  b.push_back(data_type);
  b.push_back(time_type);
  for (int i = 0; i < 12; ++i) b.push_back(0);  // reserved
  put_le(b, 0, 4);                               // crc32, filled by finish()
  put_le(b, timestamp, 8);
  return b;
}

/// Writes the CRC-32 of bytes 28.. into bytes 24..27 (bitwise reference).
inline void finish(Bytes& b) {
  const std::uint32_t c = crc32_bitwise(b.data() + 28, b.size() - 28);
  for (int i = 0; i < 4; ++i) b[24 + i] = static_cast<std::uint8_t>((c >> (8 * i)) & 0xFF);
}

inline void put_float(Bytes& b, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  put_le(b, u, 4);
}

}  // namespace porter::livox::test
