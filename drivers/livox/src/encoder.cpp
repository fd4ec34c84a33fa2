#include "porter/livox/encoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "porter/livox/crc.hpp"

namespace porter::livox {
namespace {

template <class T>
void store(std::uint8_t* p, T value) {
  std::memcpy(p, &value, sizeof value);  // little-endian hosts only (see decoder.cpp)
}

template <class Int>
Int quantize(double value, double unit) {
  const double q = std::round(value / unit);
  const double lo = static_cast<double>(std::numeric_limits<Int>::min());
  const double hi = static_cast<double>(std::numeric_limits<Int>::max());
  if (!(q >= lo)) return std::numeric_limits<Int>::min();  // also NaN
  if (q > hi) return std::numeric_limits<Int>::max();
  return static_cast<Int>(q);
}

constexpr double kPi = 3.14159265358979323846;

void write_header(const PacketInfo& info, DataType type, std::size_t count, std::size_t size,
                  std::uint8_t* out) {
  std::memset(out, 0, kHeaderSize);
  out[0] = kProtocolVersion;
  store<std::uint16_t>(out + 1, static_cast<std::uint16_t>(size));
  store<std::uint16_t>(out + 3, info.time_interval_100ns);
  store<std::uint16_t>(out + 5, static_cast<std::uint16_t>(count));
  store<std::uint16_t>(out + 7, info.udp_cnt);
  out[9] = info.frame_cnt;
  out[10] = static_cast<std::uint8_t>(type);
  out[11] = static_cast<std::uint8_t>(info.time_type);
  store<std::uint64_t>(out + kTimestampOffset, info.timestamp_ns);
}

}  // namespace

bool update_crc(std::uint8_t* packet, std::size_t size) {
  if (packet == nullptr || size < kHeaderSize) return false;
  store<std::uint32_t>(packet + kCrcOffset,
                       crc32(packet + kTimestampOffset, size - kTimestampOffset));
  return true;
}

std::size_t encode_point_packet(const PacketInfo& info, DataType type, const Point* points,
                                std::size_t count, std::uint8_t* out, std::size_t capacity) {
  if (type == DataType::kImu || count == 0 || count > kPointsPerPacket || points == nullptr ||
      out == nullptr) {
    return 0;
  }
  const std::size_t size = packet_size(type, count);
  if (capacity < size) return 0;
  write_header(info, type, count, size, out);
  std::uint8_t* p = out + kHeaderSize;
  for (std::size_t i = 0; i < count; ++i) {
    const Point& pt = points[i];
    switch (type) {
      case DataType::kCartesianHigh:
        store(p, quantize<std::int32_t>(pt.x_m, 1e-3));
        store(p + 4, quantize<std::int32_t>(pt.y_m, 1e-3));
        store(p + 8, quantize<std::int32_t>(pt.z_m, 1e-3));
        p[12] = pt.reflectivity;
        p[13] = pt.tag;
        p += 14;
        break;
      case DataType::kCartesianLow:
        store(p, quantize<std::int16_t>(pt.x_m, 1e-2));
        store(p + 2, quantize<std::int16_t>(pt.y_m, 1e-2));
        store(p + 4, quantize<std::int16_t>(pt.z_m, 1e-2));
        p[6] = pt.reflectivity;
        p[7] = pt.tag;
        p += 8;
        break;
      case DataType::kSpherical: {
        const double x = pt.x_m, y = pt.y_m, z = pt.z_m;
        const double r = std::sqrt(x * x + y * y + z * z);
        std::uint16_t theta = 0, phi = 0;
        if (r > 0.0) {
          theta = static_cast<std::uint16_t>(
              std::clamp(std::round(std::acos(std::clamp(z / r, -1.0, 1.0)) * 18000.0 / kPi),
                         0.0, 18000.0));
          double az = std::atan2(y, x);
          if (az < 0.0) az += 2.0 * kPi;
          phi = static_cast<std::uint16_t>(std::clamp(std::round(az * 18000.0 / kPi), 0.0, 36000.0));
        }
        store(p, quantize<std::uint32_t>(r, 1e-3));
        store(p + 4, theta);
        store(p + 6, phi);
        p[8] = pt.reflectivity;
        p[9] = pt.tag;
        p += 10;
        break;
      }
      case DataType::kImu:
        break;
    }
  }
  update_crc(out, size);
  return size;
}

std::size_t encode_imu_packet(const PacketInfo& info, const ImuSample& sample, std::uint8_t* out,
                              std::size_t capacity) {
  const std::size_t size = packet_size(DataType::kImu, 1);
  if (out == nullptr || capacity < size) return 0;
  write_header(info, DataType::kImu, 1, size, out);
  std::uint8_t* p = out + kHeaderSize;
  for (int k = 0; k < 3; ++k) store(p + 4 * k, sample.gyro_radps[k]);
  for (int k = 0; k < 3; ++k) store(p + 12 + 4 * k, sample.accel_g[k]);
  update_crc(out, size);
  return size;
}

}  // namespace porter::livox
