#pragma once
// The MID-360's control-command frames (Livox Ethernet protocol, "Control Command"), as far as
// porter-lidar needs them: telling the sensor where to send its point, IMU and status streams
// and to start sampling (command 0x0100, "parameter configuration"), and reading its answer.
//
// Frame (little-endian), 24-byte header then data:
//   off size field        meaning
//    0   1   sof          0xAA
//    1   1   version      0
//    2   2   length       bytes of the whole frame (max 1400)
//    4   4   seq_num      request counter; the ACK repeats it
//    8   2   cmd_id       0x0100 parameter configuration, 0x0101 inquire, ...
//   10   1   cmd_type     0 request, 1 ACK
//   11   1   sender_type  0 host, 1 LiDAR
//   12   6   reserved
//   18   2   crc16        CRC-16/CCITT-FALSE of bytes 0..17
//   20   4   crc32        CRC-32 of the data (0 when there is none)
//   24   -   data
// 0x0100 request data: uint16 key_num, uint16 reserved, then key_num entries
// {uint16 key, uint16 length, value[length]}. Its ACK data: uint8 ret_code, uint16 error_key.
// Keys used here: 0x0005 status-push, 0x0006 point-cloud and 0x0007 IMU destination, each
// {uint8 host_ip[4], uint16 host_port, uint16 lidar_port}; 0x001A target work mode (uint8,
// 0x01 sampling, 0x02 idle). Livox-SDK2 sends the three destination keys in one 0x0100 request
// when it finds a MID-360 (BuildUpdateMid360LidarCfgRequest); adding the work mode to the same
// request follows the protocol document and was not tried on a device.
//
// Failure: decode_command() returns a status and never reads outside the buffer.
// Thread-safety: reentrant.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace porter::livox {

inline constexpr std::size_t kCommandHeaderSize = 24;
inline constexpr std::size_t kMaxCommandSize = 1400;
inline constexpr std::uint16_t kCmdParameterConfig = 0x0100;
inline constexpr std::uint16_t kDefaultLidarCommandPort = 56100;
inline constexpr std::uint16_t kDefaultHostCommandPort = 56101;
inline constexpr std::uint16_t kLidarPushPort = 56200;
inline constexpr std::uint16_t kLidarPointPort = 56300;
inline constexpr std::uint16_t kLidarImuPort = 56400;

enum class CommandType : std::uint8_t { request = 0, ack = 1 };
enum class SenderType : std::uint8_t { host = 0, lidar = 1 };

enum class ConfigKey : std::uint16_t {
  state_info_host = 0x0005,
  point_host = 0x0006,
  imu_host = 0x0007,
  work_mode = 0x001A,
};
inline constexpr std::uint8_t kWorkModeSampling = 0x01;
inline constexpr std::uint8_t kWorkModeIdle = 0x02;

struct CommandFrame {
  std::uint32_t seq = 0;
  std::uint16_t cmd_id = 0;
  CommandType type = CommandType::request;
  SenderType sender = SenderType::host;
  std::vector<std::uint8_t> data;
};

enum class CommandStatus : std::uint8_t {
  ok = 0,
  too_short,        ///< fewer bytes than the 24-byte header
  bad_sof,          ///< first byte is not 0xAA
  bad_version,
  length_mismatch,  ///< header length differs from the bytes received, or exceeds 1400
  header_crc,       ///< CRC-16 of the header does not match
  data_crc,         ///< CRC-32 of the data does not match
};
const char* to_string(CommandStatus status);

/// Frame bytes of `frame` (length, CRCs filled in); empty when the data is too long.
std::vector<std::uint8_t> encode_command(const CommandFrame& frame);
CommandStatus decode_command(const std::uint8_t* bytes, std::size_t size, CommandFrame& out);

/// Destination of one stream: IPv4 address (dotted) and ports.
struct StreamDestination {
  std::array<std::uint8_t, 4> host_ip{};
  std::uint16_t host_port = 0;
  std::uint16_t lidar_port = 0;
};

/// One key of a 0x0100 request.
struct KeyValue {
  std::uint16_t key = 0;
  std::vector<std::uint8_t> value;
};

/// Data of a 0x0100 request with these keys.
std::vector<std::uint8_t> encode_key_values(const std::vector<KeyValue>& keys);
/// Parses a 0x0100 request's data; false when key_num or a length runs past the data.
bool decode_key_values(const std::vector<std::uint8_t>& data, std::vector<KeyValue>& out);

KeyValue destination_key(ConfigKey key, const StreamDestination& d);
/// Reads a destination value (8 bytes); false otherwise.
bool read_destination(const KeyValue& kv, StreamDestination& out);

/// Parses "a.b.c.d"; false when it is not an IPv4 address.
bool parse_ipv4(const std::string& text, std::array<std::uint8_t, 4>& out);
std::string format_ipv4(const std::array<std::uint8_t, 4>& ip);

/// The request porter-lidar sends: status, point and IMU streams to host_ip at the given host
/// ports, and sampling on.
CommandFrame host_config_request(std::uint32_t seq, const std::array<std::uint8_t, 4>& host_ip,
                                 std::uint16_t push_port, std::uint16_t point_port,
                                 std::uint16_t imu_port);

/// ACK data {ret_code, error_key}; false when shorter than 3 bytes.
bool read_config_ack(const std::vector<std::uint8_t>& data, std::uint8_t& ret_code,
                     std::uint16_t& error_key);
std::vector<std::uint8_t> config_ack_data(std::uint8_t ret_code, std::uint16_t error_key);

}  // namespace porter::livox
