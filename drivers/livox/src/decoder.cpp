#include "porter/livox/decoder.hpp"

#include <cmath>
#include <cstring>

#include "porter/livox/crc.hpp"

namespace porter::livox {
namespace {

template <class T>
T load(const std::uint8_t* p) {
  // Livox data is little-endian, as is every host Porter runs on (x86-64, aarch64).
  T value;
  std::memcpy(&value, p, sizeof value);
  return value;
}

constexpr double kDegPerCentiDeg = 0.01;
constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

}  // namespace

const char* to_string(DecodeStatus status) {
  switch (status) {
    case DecodeStatus::ok: return "ok";
    case DecodeStatus::too_short: return "too_short";
    case DecodeStatus::bad_version: return "bad_version";
    case DecodeStatus::length_mismatch: return "length_mismatch";
    case DecodeStatus::unknown_data_type: return "unknown_data_type";
    case DecodeStatus::bad_dot_num: return "bad_dot_num";
    case DecodeStatus::size_mismatch: return "size_mismatch";
    case DecodeStatus::unknown_time_type: return "unknown_time_type";
    case DecodeStatus::crc_mismatch: return "crc_mismatch";
    case DecodeStatus::bad_value: return "bad_value";
  }
  return "unknown";
}

std::int64_t DecodedPacket::sample_offset_ns(std::size_t i) const {
  if (header.dot_num <= 1) return 0;
  const std::int64_t span_ns = static_cast<std::int64_t>(header.time_interval_100ns) * 100;
  return span_ns * static_cast<std::int64_t>(i) / static_cast<std::int64_t>(header.dot_num - 1);
}

bool read_header(const std::uint8_t* data, std::size_t size, PacketHeader& h) {
  if (data == nullptr || size < kHeaderSize) return false;
  h.version = data[0];
  h.length = load<std::uint16_t>(data + 1);
  h.time_interval_100ns = load<std::uint16_t>(data + 3);
  h.dot_num = load<std::uint16_t>(data + 5);
  h.udp_cnt = load<std::uint16_t>(data + 7);
  h.frame_cnt = data[9];
  h.data_type = data[10];
  h.time_type = data[11];
  h.crc32 = load<std::uint32_t>(data + kCrcOffset);
  h.timestamp_ns = load<std::uint64_t>(data + kTimestampOffset);
  return true;
}

DecodeStatus decode_packet(const std::uint8_t* data, std::size_t size, const DecodeOptions& options,
                           DecodedPacket& out) {
  out.num_points = 0;
  PacketHeader& h = out.header;
  if (!read_header(data, size, h)) return DecodeStatus::too_short;
  if (h.version != kProtocolVersion) return DecodeStatus::bad_version;
  if (h.length != size) return DecodeStatus::length_mismatch;
  const std::size_t sample = sample_size(h.data_type);
  if (sample == 0) return DecodeStatus::unknown_data_type;
  const bool imu = h.data_type == static_cast<std::uint8_t>(DataType::kImu);
  if (h.dot_num == 0 || h.dot_num > kPointsPerPacket || (imu && h.dot_num != 1)) {
    return DecodeStatus::bad_dot_num;
  }
  if (kHeaderSize + sample * h.dot_num != size) return DecodeStatus::size_mismatch;
  if (h.time_type > static_cast<std::uint8_t>(TimeType::kGps)) {
    return DecodeStatus::unknown_time_type;
  }
  if (options.check_crc &&
      crc32(data + kTimestampOffset, size - kTimestampOffset) != h.crc32) {
    return DecodeStatus::crc_mismatch;
  }

  const std::uint8_t* p = data + kHeaderSize;
  switch (static_cast<DataType>(h.data_type)) {
    case DataType::kImu: {
      for (int k = 0; k < 3; ++k) out.imu.gyro_radps[k] = load<float>(p + 4 * k);
      for (int k = 0; k < 3; ++k) out.imu.accel_g[k] = load<float>(p + 12 + 4 * k);
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(out.imu.gyro_radps[k]) || !std::isfinite(out.imu.accel_g[k])) {
          return DecodeStatus::bad_value;
        }
      }
      return DecodeStatus::ok;
    }
    case DataType::kCartesianHigh:
      for (std::size_t i = 0; i < h.dot_num; ++i, p += sample) {
        Point& pt = out.points[i];
        pt.x_m = static_cast<float>(load<std::int32_t>(p) * 1e-3);
        pt.y_m = static_cast<float>(load<std::int32_t>(p + 4) * 1e-3);
        pt.z_m = static_cast<float>(load<std::int32_t>(p + 8) * 1e-3);
        pt.reflectivity = p[12];
        pt.tag = p[13];
      }
      break;
    case DataType::kCartesianLow:
      for (std::size_t i = 0; i < h.dot_num; ++i, p += sample) {
        Point& pt = out.points[i];
        pt.x_m = static_cast<float>(load<std::int16_t>(p) * 1e-2);
        pt.y_m = static_cast<float>(load<std::int16_t>(p + 2) * 1e-2);
        pt.z_m = static_cast<float>(load<std::int16_t>(p + 4) * 1e-2);
        pt.reflectivity = p[6];
        pt.tag = p[7];
      }
      break;
    case DataType::kSpherical:
      for (std::size_t i = 0; i < h.dot_num; ++i, p += sample) {
        const std::uint32_t depth_mm = load<std::uint32_t>(p);
        const std::uint16_t theta = load<std::uint16_t>(p + 4);
        const std::uint16_t phi = load<std::uint16_t>(p + 6);
        if (theta > 18000 || phi > 36000) return DecodeStatus::bad_value;
        const double r = depth_mm * 1e-3;
        const double th = theta * kDegPerCentiDeg * kRadPerDeg;
        const double ph = phi * kDegPerCentiDeg * kRadPerDeg;
        Point& pt = out.points[i];
        pt.x_m = static_cast<float>(r * std::sin(th) * std::cos(ph));
        pt.y_m = static_cast<float>(r * std::sin(th) * std::sin(ph));
        pt.z_m = static_cast<float>(r * std::cos(th));
        pt.reflectivity = p[8];
        pt.tag = p[9];
      }
      break;
  }
  out.num_points = h.dot_num;
  return DecodeStatus::ok;
}

std::uint64_t DecodeCounters::total() const {
  std::uint64_t sum = 0;
  for (std::uint64_t c : counts_) sum += c;
  return sum;
}

std::string DecodeCounters::summary() const {
  std::string s;
  for (std::size_t i = 1; i < kNumDecodeStatuses; ++i) {
    if (counts_[i] == 0) continue;
    if (!s.empty()) s += ' ';
    s += to_string(static_cast<DecodeStatus>(i));
    s += '=';
    s += std::to_string(counts_[i]);
  }
  return s;
}

}  // namespace porter::livox
