#pragma once
// The Livox MID-360 point-cloud and IMU UDP packet layout (Livox Ethernet protocol for the
// MID-360, "Point Cloud & IMU Data Protocol"), as plain values.
//
// Every datagram on the point port (default 56301) and the IMU port (default 56401) starts with
// a 36-byte little-endian header:
//
//   off size field          meaning
//    0   1   version        0
//    1   2   length         bytes of the whole datagram, header included
//    3   2   time_interval  time of the last point minus the first, units of 0.1 us
//    5   2   dot_num        number of samples in the data field
//    7   2   udp_cnt        packet counter, reset to 0 at the start of each frame
//    9   1   frame_cnt      frame counter (meaningless for the non-repetitive pattern)
//   10   1   data_type      kImu, kCartesianHigh, kCartesianLow, kSpherical
//   11   1   time_type      0 no sync (ns since power-on), 1 PTP/gPTP, 2 GPS
//   12  12   reserved
//   24   4   crc32          CRC-32 of bytes 28..length-1 (timestamp + data)
//   28   8   timestamp      time of the first sample, ns
//   36   -   data           dot_num samples of data_type's layout
//
// Samples (little-endian):
//   kImu            24 B: float gyro_x, gyro_y, gyro_z [rad/s]; float acc_x, acc_y, acc_z [g]
//   kCartesianHigh  14 B: int32 x, y, z [mm]; uint8 reflectivity; uint8 tag
//   kCartesianLow    8 B: int16 x, y, z [10 mm]; uint8 reflectivity; uint8 tag
//   kSpherical      10 B: uint32 depth [mm]; uint16 zenith theta [0.01 deg, 0..18000];
//                         uint16 azimuth phi [0.01 deg, 0..36000]; uint8 reflectivity; uint8 tag
// Point packets carry 96 samples, IMU packets one. Points are in the sensor's point frame
// (x forward, y left, z up); a point with x = y = z = 0 is "no return" (the sensor keeps the
// slot so that point times stay equally spaced). Samples in a packet are equally spaced in time
// from `timestamp` to `timestamp + time_interval`.
//
// Thread-safety: plain values and constexpr functions.

#include <array>
#include <cstddef>
#include <cstdint>

namespace porter::livox {

inline constexpr std::size_t kHeaderSize = 36;
inline constexpr std::size_t kCrcOffset = 24;
inline constexpr std::size_t kTimestampOffset = 28;
inline constexpr std::uint8_t kProtocolVersion = 0;
/// Samples in a point packet (all point data types).
inline constexpr std::uint16_t kPointsPerPacket = 96;
/// Largest datagram this protocol produces (a 96-point high-precision packet).
inline constexpr std::size_t kMaxPacketSize = kHeaderSize + 96 * 14;

/// Default host ports (Livox-SDK2 MID-360 sample configuration).
inline constexpr std::uint16_t kDefaultPointHostPort = 56301;
inline constexpr std::uint16_t kDefaultImuHostPort = 56401;

enum class DataType : std::uint8_t {
  kImu = 0,
  kCartesianHigh = 1,
  kCartesianLow = 2,
  kSpherical = 3,
};

enum class TimeType : std::uint8_t {
  kNoSync = 0,  ///< ns since the sensor powered on
  kPtp = 1,     ///< PTP / gPTP master time, ns
  kGps = 2,     ///< GPS time, ns
};

/// Bytes per sample of a data type; 0 for a byte that names no known type.
constexpr std::size_t sample_size(std::uint8_t data_type) {
  switch (data_type) {
    case 0: return 24;
    case 1: return 14;
    case 2: return 8;
    case 3: return 10;
    default: return 0;
  }
}

/// The header fields, decoded.
struct PacketHeader {
  std::uint8_t version = kProtocolVersion;
  std::uint16_t length = 0;
  std::uint16_t time_interval_100ns = 0;
  std::uint16_t dot_num = 0;
  std::uint16_t udp_cnt = 0;
  std::uint8_t frame_cnt = 0;
  std::uint8_t data_type = 0;
  std::uint8_t time_type = 0;
  std::uint32_t crc32 = 0;
  std::uint64_t timestamp_ns = 0;
};

/// One decoded point, in the sensor's point frame.
struct Point {
  float x_m = 0.0f;
  float y_m = 0.0f;
  float z_m = 0.0f;
  std::uint8_t reflectivity = 0;
  std::uint8_t tag = 0;

  /// The sensor's "no return" marker.
  bool is_no_return() const { return x_m == 0.0f && y_m == 0.0f && z_m == 0.0f; }
};

/// One IMU sample as the sensor sends it (acceleration in g, not m/s^2).
struct ImuSample {
  std::array<float, 3> gyro_radps{};
  std::array<float, 3> accel_g{};
};

/// Standard gravity, m/s^2 per g (the conversion applied to ImuSample::accel_g).
inline constexpr double kStandardGravity_mps2 = 9.80665;

}  // namespace porter::livox
