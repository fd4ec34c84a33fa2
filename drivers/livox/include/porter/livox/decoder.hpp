#pragma once
// Decoding of MID-360 point and IMU datagrams (layout in packet.hpp).
//
// decode_packet() trusts nothing in the datagram: the header's length must equal the number of
// bytes received, the data type must be known, dot_num must suit the data type (1 for IMU,
// 1..96 for points), the length must equal 36 + dot_num x sample size, the time type must be
// known, the CRC-32 must match (unless switched off) and IMU values and spherical angles must be
// in range. The first failed check is the result; nothing is read outside [data, data + size).
// A decoded point with x = y = z = 0 is the sensor's "no return" marker and is kept as such.
//
// Failure: statuses, never exceptions; DecodeCounters tallies them by reason.
// Thread-safety: decode_packet() is reentrant; a DecodeCounters belongs to one thread.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "porter/livox/packet.hpp"

namespace porter::livox {

enum class DecodeStatus : std::uint8_t {
  ok = 0,
  too_short,          ///< fewer bytes than the 36-byte header
  bad_version,        ///< version byte is not 0
  length_mismatch,    ///< header length differs from the datagram size (truncated or oversized)
  unknown_data_type,  ///< data_type is none of 0..3
  bad_dot_num,        ///< dot_num is 0, above 96, or not 1 for an IMU packet
  size_mismatch,      ///< length differs from 36 + dot_num x sample size of data_type
  unknown_time_type,  ///< time_type is none of 0..2
  crc_mismatch,       ///< CRC-32 over timestamp + data differs from the header's
  bad_value,          ///< a non-finite IMU value or a spherical angle out of range
};
inline constexpr std::size_t kNumDecodeStatuses = 10;

/// Short lower-case name ("ok", "crc_mismatch", ...).
const char* to_string(DecodeStatus status);

struct DecodeOptions {
  /// Check the CRC-32 field. Switch off only for a sensor that is known not to fill it.
  bool check_crc = true;
};

/// A decoded datagram. Fixed size (no allocation): points[0..num_points) for point packets,
/// imu for IMU packets.
struct DecodedPacket {
  PacketHeader header;
  std::array<Point, kPointsPerPacket> points;
  std::size_t num_points = 0;
  ImuSample imu;

  bool is_imu() const { return header.data_type == static_cast<std::uint8_t>(DataType::kImu); }
  /// Time of sample i after header.timestamp_ns, ns: samples are equally spaced over
  /// time_interval (first to last sample), i in [0, dot_num).
  std::int64_t sample_offset_ns(std::size_t i) const;
};

/// Decodes one datagram of `size` bytes into `out` (left in an unspecified state on failure).
DecodeStatus decode_packet(const std::uint8_t* data, std::size_t size, const DecodeOptions& options,
                           DecodedPacket& out);

/// Reads only the header fields (no checks beyond size >= 36). False when too short.
bool read_header(const std::uint8_t* data, std::size_t size, PacketHeader& out);

/// Datagrams seen, by decode status.
class DecodeCounters {
 public:
  void add(DecodeStatus status) { ++counts_[static_cast<std::size_t>(status)]; }
  std::uint64_t count(DecodeStatus status) const { return counts_[static_cast<std::size_t>(status)]; }
  std::uint64_t total() const;
  /// Every status other than ok.
  std::uint64_t malformed() const { return total() - count(DecodeStatus::ok); }
  /// "crc_mismatch=3 length_mismatch=1" for the non-zero failure reasons; "" when none.
  std::string summary() const;

 private:
  std::array<std::uint64_t, kNumDecodeStatuses> counts_{};
};

}  // namespace porter::livox
