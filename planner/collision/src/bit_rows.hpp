#pragma once
// Word-level helpers for rows of bits (bit i of a row is bit i % 64 of word i / 64).
// Private to porter_collision.

#include <cstddef>
#include <cstdint>

namespace porter::planner::bits {

/// 64 bits starting at bit `pos` of `w` (n_words words); bits past the end read as 0.
inline std::uint64_t read64(const std::uint64_t* w, std::size_t n_words, std::int64_t pos) {
  if (pos < 0) {
    if (pos <= -64) return 0;
    return read64(w, n_words, 0) << (-pos);
  }
  const auto i = static_cast<std::size_t>(pos >> 6);
  const int s = static_cast<int>(pos & 63);
  const std::uint64_t lo = i < n_words ? w[i] : 0;
  const std::uint64_t hi = i + 1 < n_words ? w[i + 1] : 0;
  return (lo >> s) | ((hi << 1) << (63 - s));
}

/// Mask of the low n bits (0 <= n <= 64).
inline std::uint64_t low_mask(int n) { return n >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1); }

/// dst |= row shifted by +s bits (towards higher x) and by -s bits; 0 < s < 64.
inline void or_shifted_both(std::uint64_t* dst, const std::uint64_t* row, std::int64_t n_words, int s) {
  for (std::int64_t k = 0; k < n_words; ++k) {
    std::uint64_t up = row[k] << s;
    if (k > 0) up |= row[k - 1] >> (64 - s);
    std::uint64_t down = row[k] >> s;
    if (k + 1 < n_words) down |= row[k + 1] << (64 - s);
    dst[k] |= up | down;
  }
}

/// dst |= row dilated along x by `a` bits on each side (0 <= a < 64).
inline void or_dilated(std::uint64_t* dst, const std::uint64_t* row, std::int64_t n_words, int a) {
  for (std::int64_t k = 0; k < n_words; ++k) dst[k] |= row[k];
  for (int s = 1; s <= a; ++s) or_shifted_both(dst, row, n_words, s);
}

}  // namespace porter::planner::bits
