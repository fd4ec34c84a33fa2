#pragma once
// One classic CAN 2.0 frame, as every transport and protocol library in Porter sees it.

#include <array>
#include <cstdint>
#include <string>

namespace porter::can {

struct CanFrame {
  std::uint32_t id = 0;              ///< 11-bit (standard) or 29-bit (extended) arbitration ID
  bool extended = false;             ///< 29-bit ID
  bool rtr = false;                  ///< remote transmission request: no data
  std::uint8_t dlc = 0;              ///< data length 0..8
  std::array<std::uint8_t, 8> data{};  ///< bytes [0, dlc) are valid; the rest are zero
  std::int64_t utime = 0;            ///< receive (or send) time, µs since the epoch; 0 = unknown

  /// True when the ID fits its format and dlc <= 8.
  bool valid() const {
    return dlc <= 8 && (extended ? id <= 0x1FFFFFFFu : id <= 0x7FFu);
  }
};

/// "0x111 [8] 00 96 00 00 00 00 00 00" (candump-like; for logs and test failures).
inline std::string to_string(const CanFrame& f) {
  static const char* hex = "0123456789ABCDEF";
  std::string s = "0x";
  const int digits = f.extended ? 8 : 3;
  for (int i = digits - 1; i >= 0; --i) s += hex[(f.id >> (4 * i)) & 0xF];
  s += f.rtr ? " R[" : " [";
  s += static_cast<char>('0' + (f.dlc > 8 ? 8 : f.dlc));
  s += ']';
  for (int i = 0; i < f.dlc && i < 8; ++i) {
    s += ' ';
    s += hex[f.data[i] >> 4];
    s += hex[f.data[i] & 0xF];
  }
  return s;
}

inline bool operator==(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.extended != b.extended || a.rtr != b.rtr || a.dlc != b.dlc) return false;
  for (int i = 0; i < a.dlc && i < 8; ++i) {
    if (a.data[i] != b.data[i]) return false;
  }
  return true;
}
inline bool operator!=(const CanFrame& a, const CanFrame& b) { return !(a == b); }

}  // namespace porter::can
