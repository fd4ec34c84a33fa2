#include "porter/livox/crc.hpp"

#include <array>

namespace porter::livox {
namespace {

constexpr std::array<std::uint32_t, 256> make_crc32_table() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : (c >> 1);
    table[i] = c;
  }
  return table;
}

constexpr std::array<std::uint16_t, 256> make_crc16_table() {
  std::array<std::uint16_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i << 8;
    for (int k = 0; k < 8; ++k) c = (c & 0x8000u) ? (c << 1) ^ 0x1021u : (c << 1);
    table[i] = static_cast<std::uint16_t>(c);
  }
  return table;
}

constexpr std::array<std::uint32_t, 256> kCrc32Table = make_crc32_table();
constexpr std::array<std::uint16_t, 256> kCrc16Table = make_crc16_table();

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc) {
  std::uint32_t c = ~crc;
  for (std::size_t i = 0; i < size; ++i) c = kCrc32Table[(c ^ data[i]) & 0xFFu] ^ (c >> 8);
  return ~c;
}

std::uint16_t crc16_ccitt_false(const std::uint8_t* data, std::size_t size) {
  std::uint16_t c = 0xFFFF;
  for (std::size_t i = 0; i < size; ++i) {
    c = static_cast<std::uint16_t>((c << 8) ^ kCrc16Table[((c >> 8) ^ data[i]) & 0xFFu]);
  }
  return c;
}

}  // namespace porter::livox
