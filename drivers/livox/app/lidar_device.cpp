#include "lidar_device.hpp"

#include <cstdio>
#include <vector>

#include "porter/runtime/log.hpp"

namespace porter::livox::app {

namespace rt = porter::runtime;

std::optional<DeviceConfigurator> DeviceConfigurator::open(const DeviceParams& params, std::uint16_t point_port,
                                                           std::uint16_t imu_port, std::string& error) {
  std::array<std::uint8_t, 4> host_ip{};
  if (!parse_ipv4(params.host_address, host_ip)) {
    error = "device.host_address '" + params.host_address + "' is not an IPv4 address";
    return std::nullopt;
  }
  auto socket = UdpEndpoint::open("0.0.0.0", params.host_command_port, error);
  if (!socket) return std::nullopt;
  return DeviceConfigurator(params, host_ip, point_port, imu_port, std::move(*socket));
}

void DeviceConfigurator::step(std::int64_t now_ns, bool stream_alive) {
  std::vector<std::uint8_t> reply;
  bool truncated = false;
  std::string from;
  std::uint16_t from_port = 0;
  while (socket_.receive_from(reply, truncated, from, from_port) > 0) {
    CommandFrame f;
    const CommandStatus s = truncated ? CommandStatus::length_mismatch : decode_command(reply.data(), reply.size(), f);
    if (s != CommandStatus::ok) {
      ++bad_replies_;
      rt::log_warn("sensor command reply from " + from + ":" + std::to_string(from_port) + " rejected: " + to_string(s));
      continue;
    }
    if (f.type != CommandType::ack || f.cmd_id != kCmdParameterConfig || f.seq != seq_) continue;
    std::uint8_t ret = 0;
    std::uint16_t key = 0;
    if (!read_config_ack(f.data, ret, key)) {
      ++bad_replies_;
      rt::log_warn("sensor configuration ACK too short");
    } else if (ret != 0) {
      char text[64];
      std::snprintf(text, sizeof text, "ret_code 0x%02X, key 0x%04X", ret, key);
      rt::log_warn(std::string("sensor refused the configuration: ") + text);
    } else if (!acknowledged_) {
      acknowledged_ = true;
      rt::log_info("sensor " + params_.lidar_address + " configured: points to " + params_.host_address + ":" +
                   std::to_string(point_port_) + ", IMU to :" + std::to_string(imu_port_) + ", sampling");
    }
  }
  // A stream that stops after being acknowledged needs the sensor configured again.
  if (was_alive_ && !stream_alive) acknowledged_ = false;
  was_alive_ = stream_alive;
  if (acknowledged_ || now_ns < next_request_ns_) return;
  const auto bytes = encode_command(host_config_request(++seq_, host_ip_, params_.host_push_port, point_port_, imu_port_));
  if (socket_.send_to(params_.lidar_address, params_.lidar_command_port, bytes.data(), bytes.size()) < 0) {
    rt::log_warn("sensor configuration request: " + socket_.last_error());
  } else if (requests_ == 0 || requests_ % 10 == 0) {
    rt::log_info("sent the sensor configuration request to " + params_.lidar_address + ":" +
                 std::to_string(params_.lidar_command_port) + " (attempt " + std::to_string(requests_ + 1) + ")");
  }
  ++requests_;
  next_request_ns_ = now_ns + static_cast<std::int64_t>(params_.retry_period_s * 1e9);
}

}  // namespace porter::livox::app
