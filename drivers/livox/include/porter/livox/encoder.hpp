#pragma once
// Encoding of MID-360 point and IMU datagrams (layout in packet.hpp): the simulated MID-360
// sends what these produce, and the tests build packets with them.
//
// Coordinates are rounded to the data type's unit (1 mm, 10 mm, or 1 mm / 0.01 deg for the
// spherical type) and clamped to its integer range (+-327.67 m for the 16-bit type). A point at
// the origin encodes the "no return" marker. length, dot_num, data_type and the CRC-32 are
// filled in by the encoder; the other header fields come from PacketInfo.
//
// Failure: 0 bytes written when `capacity` is too small or the sample count is not 1..96.
// Thread-safety: reentrant.

#include <cstddef>
#include <cstdint>

#include "porter/livox/packet.hpp"

namespace porter::livox {

/// Header fields the caller chooses.
struct PacketInfo {
  std::uint16_t time_interval_100ns = 0;  ///< first to last sample, 0.1 us
  std::uint16_t udp_cnt = 0;
  std::uint8_t frame_cnt = 0;
  TimeType time_type = TimeType::kNoSync;
  std::uint64_t timestamp_ns = 0;         ///< time of the first sample
};

/// Bytes of a packet of `count` samples of `type`.
constexpr std::size_t packet_size(DataType type, std::size_t count) {
  return kHeaderSize + sample_size(static_cast<std::uint8_t>(type)) * count;
}

/// Writes a point packet of `count` points (type must not be kImu). Returns its size or 0.
std::size_t encode_point_packet(const PacketInfo& info, DataType type, const Point* points,
                                std::size_t count, std::uint8_t* out, std::size_t capacity);

/// Writes an IMU packet (one sample, acceleration in g). Returns its size or 0.
std::size_t encode_imu_packet(const PacketInfo& info, const ImuSample& sample, std::uint8_t* out,
                              std::size_t capacity);

/// Recomputes the CRC-32 field of a packet whose bytes were edited (tests). False when the
/// buffer is shorter than the header.
bool update_crc(std::uint8_t* packet, std::size_t size);

}  // namespace porter::livox
