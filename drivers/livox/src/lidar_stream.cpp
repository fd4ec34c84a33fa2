#include "porter/livox/lidar_stream.hpp"

#include <cmath>

namespace porter::livox {

LidarStream::LidarStream(const LidarStreamParams& params)
    : params_(params), host_time_(params.host_time), assembler_(params.cloud) {}

void LidarStream::handle(const std::uint8_t* data, std::size_t size, bool truncated,
                         std::int64_t receive_ns, std::vector<Cloud>& clouds,
                         std::vector<ImuMeasurement>& imu) {
  if (truncated) {
    counters_.decode.add(DecodeStatus::length_mismatch);
    return;
  }
  const DecodeStatus status = decode_packet(data, size, params_.decode, packet_);
  counters_.decode.add(status);
  if (status != DecodeStatus::ok) return;
  const PacketHeader& h = packet_.header;
  const std::int64_t span_ns = static_cast<std::int64_t>(h.time_interval_100ns) * 100;
  const std::int64_t sensor_ns = static_cast<std::int64_t>(h.timestamp_ns);
  const bool synced = h.time_type != static_cast<std::uint8_t>(TimeType::kNoSync);
  const std::int64_t first_ns =
      synced ? sensor_ns : host_time_.map(h.timestamp_ns, span_ns, receive_ns, packet_.is_imu() ? 1 : 0);

  if (packet_.is_imu()) {
    ++counters_.imu_packets;
    if (have_imu_) {
      const std::uint16_t expected = static_cast<std::uint16_t>(last_imu_cnt_ + 1);
      const std::uint16_t gap = static_cast<std::uint16_t>(h.udp_cnt - expected);
      // A small forward gap is loss; anything else is a counter restart.
      if (gap != 0 && gap < 1000) counters_.lost_imu_packets += gap;
    }
    have_imu_ = true;
    last_imu_cnt_ = h.udp_cnt;
    last_imu_receive_ns_ = receive_ns;
    ImuMeasurement m;
    m.time_ns = first_ns;
    m.time_type = h.time_type;
    m.sample = packet_.imu;
    imu.push_back(m);
    return;
  }

  ++counters_.point_packets;
  if (have_point_ && h.dot_num > 1) {
    const double period_ns = static_cast<double>(span_ns) * h.dot_num / (h.dot_num - 1);
    const std::int64_t dt = sensor_ns - last_point_sensor_ns_;
    if (dt < 0) {
      ++counters_.reordered_packets;
    } else if (period_ns > 0.0) {
      const double steps = std::round(static_cast<double>(dt) / period_ns);
      // A jump of more than a second is a clock change, not loss.
      if (steps > 1.0 && steps * period_ns < 1e9) {
        counters_.lost_point_packets += static_cast<std::uint64_t>(steps - 1.0);
      }
    }
  }
  have_point_ = true;
  last_point_sensor_ns_ = sensor_ns;
  last_point_receive_ns_ = receive_ns;
  const std::size_t before = clouds.size();
  assembler_.add(packet_, first_ns, clouds);
  for (std::size_t i = before; i < clouds.size(); ++i) {
    ++counters_.clouds;
    counters_.points += clouds[i].size();
  }
}

bool LidarStream::flush_if_idle(std::int64_t now_ns, double idle_s, std::vector<Cloud>& clouds) {
  if (assembler_.empty()) return false;
  if (now_ns - last_point_receive_ns_ < static_cast<std::int64_t>(idle_s * 1e9)) return false;
  const std::size_t before = clouds.size();
  if (!assembler_.flush(clouds)) return false;
  for (std::size_t i = before; i < clouds.size(); ++i) {
    ++counters_.clouds;
    counters_.points += clouds[i].size();
  }
  return true;
}

std::string LidarStream::summary() const {
  std::string s = "malformed " + std::to_string(counters_.decode.malformed());
  const std::string reasons = counters_.decode.summary();
  if (!reasons.empty()) s += " (" + reasons + ")";
  s += ", lost " + std::to_string(counters_.lost_point_packets) + " point + " +
       std::to_string(counters_.lost_imu_packets) + " imu packets";
  if (counters_.reordered_packets > 0) {
    s += ", reordered " + std::to_string(counters_.reordered_packets);
  }
  s += ", no-return " + std::to_string(assembler_.no_return_points());
  if (assembler_.points_over_capacity() > 0) {
    s += ", over capacity " + std::to_string(assembler_.points_over_capacity());
  }
  if (host_time_.resets() > 0) s += ", clock resets " + std::to_string(host_time_.resets());
  if (host_time_.steps_back() > 0) s += ", clock steps back " + std::to_string(host_time_.steps_back());
  return s;
}

}  // namespace porter::livox
