// Fuzz target: a datagram on porter-lidar's point or IMU port. Decodes it with and without the
// CRC check, re-encodes what decoded and checks the round trip, and feeds it through the
// driver's stream handling (host clock, loss counting, cloud assembly). A decoder that reads
// outside the datagram, crashes or loses a field in the round trip aborts.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "porter/livox/decoder.hpp"
#include "porter/livox/encoder.hpp"
#include "porter/livox/lidar_stream.hpp"

using namespace porter::livox;

namespace {

void check_round_trip(const DecodedPacket& d) {
  std::uint8_t out[kMaxPacketSize];
  PacketInfo info;
  info.time_interval_100ns = d.header.time_interval_100ns;
  info.udp_cnt = d.header.udp_cnt;
  info.frame_cnt = d.header.frame_cnt;
  info.time_type = static_cast<TimeType>(d.header.time_type);
  info.timestamp_ns = d.header.timestamp_ns;
  std::size_t n = 0;
  if (d.is_imu()) {
    n = encode_imu_packet(info, d.imu, out, sizeof out);
  } else {
    n = encode_point_packet(info, static_cast<DataType>(d.header.data_type), d.points.data(),
                            d.num_points, out, sizeof out);
  }
  if (n != d.header.length) std::abort();
  DecodedPacket again;
  if (decode_packet(out, n, {}, again) != DecodeStatus::ok) std::abort();
  if (again.num_points != d.num_points || again.header.timestamp_ns != d.header.timestamp_ns ||
      again.header.udp_cnt != d.header.udp_cnt) {
    std::abort();
  }
  if (d.header.data_type == static_cast<std::uint8_t>(DataType::kCartesianHigh) ||
      d.header.data_type == static_cast<std::uint8_t>(DataType::kCartesianLow)) {
    for (std::size_t i = 0; i < d.num_points; ++i) {
      if (again.points[i].x_m != d.points[i].x_m || again.points[i].y_m != d.points[i].y_m ||
          again.points[i].z_m != d.points[i].z_m || again.points[i].tag != d.points[i].tag) {
        std::abort();
      }
    }
  }
  for (std::size_t i = 0; i < d.num_points; ++i) {
    if (!std::isfinite(d.points[i].x_m) || !std::isfinite(d.points[i].y_m) || !std::isfinite(d.points[i].z_m)) {
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // An exact-size copy: a read past the datagram is a read past the allocation.
  const std::vector<std::uint8_t> datagram(data, data + size);
  DecodedPacket d;
  DecodeOptions no_crc;
  no_crc.check_crc = false;
  if (decode_packet(datagram.data(), datagram.size(), no_crc, d) == DecodeStatus::ok) check_round_trip(d);
  (void)decode_packet(datagram.data(), datagram.size(), {}, d);

  static LidarStream stream(LidarStreamParams{});
  static std::int64_t receive_ns = 1'700'000'000'000'000'000LL;
  static std::vector<Cloud> clouds;
  static std::vector<ImuMeasurement> imu;
  receive_ns += 480000;
  stream.handle(datagram.data(), datagram.size(), false, receive_ns, clouds, imu);
  for (const Cloud& c : clouds) {
    if (c.x_m.size() != c.time_offset_ns.size() || c.line.size() != c.x_m.size()) std::abort();
  }
  clouds.clear();
  imu.clear();
  return 0;
}
