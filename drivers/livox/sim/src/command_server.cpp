#include "porter/livox_sim/command_server.hpp"

#include <vector>

namespace porter::livox::sim {

std::optional<CommandServer> CommandServer::open(const std::string& address, std::uint16_t port,
                                                 std::string& error) {
  auto socket = UdpEndpoint::open(address, port, error);
  if (!socket) return std::nullopt;
  return CommandServer(std::move(*socket));
}

std::size_t CommandServer::poll(RealtimeSender& sender) {
  std::size_t applied = 0;
  std::vector<std::uint8_t> bytes;
  bool truncated = false;
  std::string from;
  std::uint16_t from_port = 0;
  while (socket_.receive_from(bytes, truncated, from, from_port) > 0) {
    CommandFrame request;
    if (truncated || decode_command(bytes.data(), bytes.size(), request) != CommandStatus::ok) {
      ++bad_frames_;
      continue;
    }
    if (request.type != CommandType::request || request.cmd_id != kCmdParameterConfig) continue;
    std::vector<KeyValue> keys;
    std::uint8_t ret = 0;
    std::uint16_t bad_key = 0;
    if (!decode_key_values(request.data, keys)) {
      ret = 0x24;  // key_num and key list disagree
    } else {
      for (const KeyValue& kv : keys) {
        StreamDestination d;
        const bool destination = kv.key == static_cast<std::uint16_t>(ConfigKey::point_host) ||
                                 kv.key == static_cast<std::uint16_t>(ConfigKey::imu_host) ||
                                 kv.key == static_cast<std::uint16_t>(ConfigKey::state_info_host);
        if (destination && !read_destination(kv, d)) {
          ret = 0x23;  // wrong value length
        } else if (kv.key == static_cast<std::uint16_t>(ConfigKey::work_mode)) {
          if (kv.value.size() != 1 || (kv.value[0] != kWorkModeSampling && kv.value[0] != kWorkModeIdle)) ret = 0x03;
        } else if (!destination) {
          ret = 0x20;  // not supported
        }
        if (ret != 0) {
          bad_key = kv.key;
          break;
        }
      }
    }
    if (ret == 0) {
      last_applied_.clear();
      for (const KeyValue& kv : keys) {
        StreamDestination d;
        if (kv.key == static_cast<std::uint16_t>(ConfigKey::work_mode)) {
          sender.set_sampling(kv.value[0] == kWorkModeSampling);
          last_applied_ += kv.value[0] == kWorkModeSampling ? " sampling" : " idle";
        } else if (read_destination(kv, d) && kv.key != static_cast<std::uint16_t>(ConfigKey::state_info_host)) {
          const auto stream = kv.key == static_cast<std::uint16_t>(ConfigKey::point_host)
                                  ? SimPacket::Stream::points : SimPacket::Stream::imu;
          const std::string address = format_ipv4(d.host_ip);
          if (!sender.set_destination(stream, address, d.host_port)) {
            ret = 0x01;
            bad_key = kv.key;
            break;
          }
          last_applied_ += std::string(stream == SimPacket::Stream::points ? " points" : " imu") + " to " +
                           address + ":" + std::to_string(d.host_port);
        }
      }
    }
    CommandFrame ack;
    ack.seq = request.seq;
    ack.cmd_id = request.cmd_id;
    ack.type = CommandType::ack;
    ack.sender = SenderType::lidar;
    ack.data = config_ack_data(ret, bad_key);
    const auto reply = encode_command(ack);
    socket_.send_to(from, from_port, reply.data(), reply.size());
    if (ret == 0) ++applied;
  }
  return applied;
}

}  // namespace porter::livox::sim
