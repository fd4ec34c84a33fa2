#include "porter/livox/command.hpp"

#include <cstdio>
#include <cstring>

#include "porter/livox/crc.hpp"

namespace porter::livox {
namespace {

template <class T>
void put(std::vector<std::uint8_t>& b, T v) {
  std::uint8_t raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));  // little-endian hosts only (see decoder.cpp)
  for (std::uint8_t byte : raw) b.push_back(byte);
}

template <class T>
T load(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

const char* to_string(CommandStatus status) {
  switch (status) {
    case CommandStatus::ok: return "ok";
    case CommandStatus::too_short: return "too_short";
    case CommandStatus::bad_sof: return "bad_sof";
    case CommandStatus::bad_version: return "bad_version";
    case CommandStatus::length_mismatch: return "length_mismatch";
    case CommandStatus::header_crc: return "header_crc";
    case CommandStatus::data_crc: return "data_crc";
  }
  return "unknown";
}

std::vector<std::uint8_t> encode_command(const CommandFrame& f) {
  const std::size_t length = kCommandHeaderSize + f.data.size();
  if (length > kMaxCommandSize) return {};
  std::vector<std::uint8_t> b;
  b.reserve(length);
  b.push_back(0xAA);
  b.push_back(0);
  put<std::uint16_t>(b, static_cast<std::uint16_t>(length));
  put<std::uint32_t>(b, f.seq);
  put<std::uint16_t>(b, f.cmd_id);
  b.push_back(static_cast<std::uint8_t>(f.type));
  b.push_back(static_cast<std::uint8_t>(f.sender));
  b.insert(b.end(), 6, 0);
  put<std::uint16_t>(b, crc16_ccitt_false(b.data(), 18));
  put<std::uint32_t>(b, f.data.empty() ? 0u : crc32(f.data.data(), f.data.size()));
  b.insert(b.end(), f.data.begin(), f.data.end());
  return b;
}

CommandStatus decode_command(const std::uint8_t* p, std::size_t size, CommandFrame& out) {
  if (p == nullptr || size < kCommandHeaderSize) return CommandStatus::too_short;
  if (p[0] != 0xAA) return CommandStatus::bad_sof;
  if (p[1] != 0) return CommandStatus::bad_version;
  const std::uint16_t length = load<std::uint16_t>(p + 2);
  if (length != size || length > kMaxCommandSize) return CommandStatus::length_mismatch;
  if (load<std::uint16_t>(p + 18) != crc16_ccitt_false(p, 18)) return CommandStatus::header_crc;
  const std::size_t n = size - kCommandHeaderSize;
  const std::uint32_t data_crc = n == 0 ? 0u : crc32(p + kCommandHeaderSize, n);
  if (load<std::uint32_t>(p + 20) != data_crc) return CommandStatus::data_crc;
  out.seq = load<std::uint32_t>(p + 4);
  out.cmd_id = load<std::uint16_t>(p + 8);
  out.type = static_cast<CommandType>(p[10]);
  out.sender = static_cast<SenderType>(p[11]);
  out.data.assign(p + kCommandHeaderSize, p + size);
  return CommandStatus::ok;
}

std::vector<std::uint8_t> encode_key_values(const std::vector<KeyValue>& keys) {
  std::vector<std::uint8_t> b;
  put<std::uint16_t>(b, static_cast<std::uint16_t>(keys.size()));
  put<std::uint16_t>(b, 0);
  for (const KeyValue& kv : keys) {
    put<std::uint16_t>(b, kv.key);
    put<std::uint16_t>(b, static_cast<std::uint16_t>(kv.value.size()));
    b.insert(b.end(), kv.value.begin(), kv.value.end());
  }
  return b;
}

bool decode_key_values(const std::vector<std::uint8_t>& data, std::vector<KeyValue>& out) {
  out.clear();
  if (data.size() < 4) return false;
  const std::uint16_t n = load<std::uint16_t>(data.data());
  std::size_t at = 4;
  for (std::uint16_t i = 0; i < n; ++i) {
    if (data.size() - at < 4) return false;
    KeyValue kv;
    kv.key = load<std::uint16_t>(data.data() + at);
    const std::uint16_t len = load<std::uint16_t>(data.data() + at + 2);
    at += 4;
    if (data.size() - at < len) return false;
    kv.value.assign(data.begin() + static_cast<std::ptrdiff_t>(at),
                    data.begin() + static_cast<std::ptrdiff_t>(at + len));
    at += len;
    out.push_back(std::move(kv));
  }
  return at == data.size();
}

KeyValue destination_key(ConfigKey key, const StreamDestination& d) {
  KeyValue kv;
  kv.key = static_cast<std::uint16_t>(key);
  kv.value.assign(d.host_ip.begin(), d.host_ip.end());
  put<std::uint16_t>(kv.value, d.host_port);
  put<std::uint16_t>(kv.value, d.lidar_port);
  return kv;
}

bool read_destination(const KeyValue& kv, StreamDestination& out) {
  if (kv.value.size() != 8) return false;
  for (int i = 0; i < 4; ++i) out.host_ip[i] = kv.value[i];
  out.host_port = load<std::uint16_t>(kv.value.data() + 4);
  out.lidar_port = load<std::uint16_t>(kv.value.data() + 6);
  return true;
}

bool parse_ipv4(const std::string& text, std::array<std::uint8_t, 4>& out) {
  unsigned a[4];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%u.%u.%u.%u%c", &a[0], &a[1], &a[2], &a[3], &tail) != 4) return false;
  for (int i = 0; i < 4; ++i) {
    if (a[i] > 255) return false;
    out[i] = static_cast<std::uint8_t>(a[i]);
  }
  return true;
}

std::string format_ipv4(const std::array<std::uint8_t, 4>& ip) {
  return std::to_string(ip[0]) + "." + std::to_string(ip[1]) + "." + std::to_string(ip[2]) + "." +
         std::to_string(ip[3]);
}

CommandFrame host_config_request(std::uint32_t seq, const std::array<std::uint8_t, 4>& host_ip,
                                 std::uint16_t push_port, std::uint16_t point_port,
                                 std::uint16_t imu_port) {
  CommandFrame f;
  f.seq = seq;
  f.cmd_id = kCmdParameterConfig;
  f.type = CommandType::request;
  f.sender = SenderType::host;
  KeyValue mode;
  mode.key = static_cast<std::uint16_t>(ConfigKey::work_mode);
  mode.value = {kWorkModeSampling};
  f.data = encode_key_values({destination_key(ConfigKey::state_info_host, {host_ip, push_port, kLidarPushPort}),
                              destination_key(ConfigKey::point_host, {host_ip, point_port, kLidarPointPort}),
                              destination_key(ConfigKey::imu_host, {host_ip, imu_port, kLidarImuPort}),
                              mode});
  return f;
}

bool read_config_ack(const std::vector<std::uint8_t>& data, std::uint8_t& ret_code, std::uint16_t& error_key) {
  if (data.size() < 3) return false;
  ret_code = data[0];
  error_key = load<std::uint16_t>(data.data() + 1);
  return true;
}

std::vector<std::uint8_t> config_ack_data(std::uint8_t ret_code, std::uint16_t error_key) {
  std::vector<std::uint8_t> b{ret_code};
  put<std::uint16_t>(b, error_key);
  return b;
}

}  // namespace porter::livox
