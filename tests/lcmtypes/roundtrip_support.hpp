#pragma once
// Helpers for the lcmtypes round-trip tests: encode, check the wire header, decode into a fresh
// object.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace porter::test {

/// Big-endian int64 at `offset` of an encoded buffer.
inline std::int64_t read_be_int64(const std::vector<std::uint8_t>& buf, std::size_t offset) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < 8; ++i) v = (v << 8) | buf.at(offset + i);
  return static_cast<std::int64_t>(v);
}

template <class T>
std::vector<std::uint8_t> encode(const T& msg) {
  const int size = msg.getEncodedSize();
  EXPECT_GT(size, 16);
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(size));
  EXPECT_EQ(msg.encode(buf.data(), 0, size), size);
  return buf;
}

/// Encodes `msg`, checks the fingerprint and that `utime` is the first field on the wire, and
/// decodes the bytes into a new T.
template <class T>
T roundtrip(const T& msg) {
  const std::vector<std::uint8_t> buf = encode(msg);
  EXPECT_EQ(read_be_int64(buf, 0), T::getHash()) << T::getTypeName() << ": fingerprint";
  EXPECT_EQ(read_be_int64(buf, 8), msg.utime) << T::getTypeName() << ": utime must come first";
  T out;
  EXPECT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()))
      << T::getTypeName() << ": decode";
  return out;
}

/// A truncated buffer and a buffer of another type must both be rejected by T's decoder.
template <class T, class Other>
void expect_rejects(const T& msg, const Other& other) {
  std::vector<std::uint8_t> buf = encode(msg);
  T out;
  EXPECT_LT(out.decode(buf.data(), 0, static_cast<int>(buf.size()) - 1), 0)
      << T::getTypeName() << ": truncated buffer accepted";
  const std::vector<std::uint8_t> other_buf = encode(other);
  EXPECT_LT(out.decode(other_buf.data(), 0, static_cast<int>(other_buf.size())), 0)
      << T::getTypeName() << " decoded a " << Other::getTypeName();
}

}  // namespace porter::test
