#include "porter/livox_sim/realtime_sender.hpp"

namespace porter::livox::sim {

std::optional<RealtimeSender> RealtimeSender::open(const RealtimeSenderParams& params,
                                                   std::string& error) {
  auto points = UdpSender::open(params.destination, params.point_port, params.point_source_port, error);
  if (!points) return std::nullopt;
  auto imu = UdpSender::open(params.destination, params.imu_port, params.imu_source_port, error);
  if (!imu) return std::nullopt;
  return RealtimeSender(params, std::move(*points), std::move(*imu));
}

std::size_t RealtimeSender::step(SimulatedMid360& lidar, double now_s) {
  if (!(now_s > last_s_)) return 0;
  packets_.clear();
  lidar.advance(last_s_, now_s, packets_);
  last_s_ = now_s;
  return send(packets_);
}

std::size_t RealtimeSender::send(const std::vector<SimPacket>& packets) {
  if (!sampling_) return 0;
  std::size_t sent = 0;
  for (const SimPacket& p : packets) {
    UdpSender& socket = p.stream == SimPacket::Stream::points ? points_ : imu_;
    const long n = socket.send(p.bytes.data(), p.size);
    if (n == static_cast<long>(p.size)) {
      ++sent;
    } else {
      ++failures_;
      if (n < 0) last_error_ = socket.last_error();
    }
  }
  sent_ += sent;
  return sent;
}

bool RealtimeSender::set_destination(SimPacket::Stream stream, const std::string& address, std::uint16_t port) {
  const bool points = stream == SimPacket::Stream::points;
  std::string error;
  auto socket = UdpSender::open(address, port, points ? params_.point_source_port : params_.imu_source_port, error);
  if (!socket) {
    last_error_ = error;
    return false;
  }
  (points ? points_ : imu_) = std::move(*socket);
  (points ? params_.point_port : params_.imu_port) = port;
  params_.destination = address;
  return true;
}

}  // namespace porter::livox::sim
