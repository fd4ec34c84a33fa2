// MID-360 control-command frames against hand-built bytes; key-value lists; malformed frames.
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "packet_bytes.hpp"
#include "porter/livox/command.hpp"

namespace porter::livox {
namespace {

using test::Bytes;

/// A frame written field by field from the protocol's table.
Bytes hand_built(std::uint32_t seq, std::uint16_t cmd, std::uint8_t type, std::uint8_t sender, const Bytes& data) {
  Bytes b;
  b.push_back(0xAA);
  b.push_back(0);
  test::put_le(b, 24 + data.size(), 2);
  test::put_le(b, seq, 4);
  test::put_le(b, cmd, 2);
  b.push_back(type);
  b.push_back(sender);
  for (int i = 0; i < 6; ++i) b.push_back(0);
  test::put_le(b, test::crc16_bitwise(b.data(), 18), 2);
  test::put_le(b, data.empty() ? 0 : test::crc32_bitwise(data.data(), data.size()), 4);
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

TEST(LivoxCommand, EncodesTheProtocolsFrameAndDecodesIt) {
  const Bytes data = {0x01, 0x00, 0x00, 0x00, 0x1A, 0x00, 0x01, 0x00, 0x01};  // work mode: sampling
  CommandFrame f;
  f.seq = 0x01020304;
  f.cmd_id = 0x0100;
  f.data = data;
  const Bytes expected = hand_built(0x01020304, 0x0100, 0, 0, data);
  EXPECT_EQ(encode_command(f), expected);
  CommandFrame d;
  ASSERT_EQ(decode_command(expected.data(), expected.size(), d), CommandStatus::ok);
  EXPECT_EQ(d.seq, 0x01020304u);
  EXPECT_EQ(d.cmd_id, 0x0100);
  EXPECT_EQ(d.type, CommandType::request);
  EXPECT_EQ(d.sender, SenderType::host);
  EXPECT_EQ(d.data, data);
  // No data: the CRC-32 field is 0.
  CommandFrame empty;
  empty.cmd_id = 0x0101;
  empty.type = CommandType::ack;
  empty.sender = SenderType::lidar;
  const Bytes e = encode_command(empty);
  EXPECT_EQ(e, hand_built(0, 0x0101, 1, 1, {}));
  EXPECT_EQ(e[20] | e[21] | e[22] | e[23], 0);
}

TEST(LivoxCommand, MalformedFramesHaveTheirReasons) {
  const Bytes good = hand_built(7, 0x0100, 1, 1, {0, 0, 0});
  CommandFrame d;
  for (std::size_t n = 0; n < good.size(); ++n) {
    const Bytes cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_EQ(decode_command(cut.data(), cut.size(), d),
              n < 24 ? CommandStatus::too_short : CommandStatus::length_mismatch);
  }
  Bytes b = good;
  b[0] = 0xAB;
  EXPECT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::bad_sof);
  b = good;
  b[1] = 1;
  EXPECT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::bad_version);
  b = good;
  b[9] ^= 1;  // cmd_id changed: the header CRC no longer matches
  EXPECT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::header_crc);
  b = good;
  b[25] ^= 1;
  EXPECT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::data_crc);
  b = good;
  b.push_back(0);
  EXPECT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::length_mismatch);
  CommandFrame big;
  big.data.resize(1400);
  EXPECT_TRUE(encode_command(big).empty());
}

TEST(LivoxCommand, HostConfigurationRequestCarriesTheDestinationsAndSampling) {
  std::array<std::uint8_t, 4> ip{};
  ASSERT_TRUE(parse_ipv4("192.168.1.5", ip));
  const CommandFrame f = host_config_request(9, ip, 56201, 56301, 56401);
  EXPECT_EQ(f.cmd_id, kCmdParameterConfig);
  // Hand-built data: key_num 4, then {key, length 8, ip, host port, lidar port} x 3, work mode.
  Bytes expected;
  test::put_le(expected, 4, 2);
  test::put_le(expected, 0, 2);
  const std::uint16_t keys[3][3] = {{0x0005, 56201, 56200}, {0x0006, 56301, 56300}, {0x0007, 56401, 56400}};
  for (const auto& k : keys) {
    test::put_le(expected, k[0], 2);
    test::put_le(expected, 8, 2);
    for (int v : {192, 168, 1, 5}) expected.push_back(static_cast<std::uint8_t>(v));
    test::put_le(expected, k[1], 2);
    test::put_le(expected, k[2], 2);
  }
  test::put_le(expected, 0x001A, 2);
  test::put_le(expected, 1, 2);
  expected.push_back(0x01);
  EXPECT_EQ(f.data, expected);
  std::vector<KeyValue> kv;
  ASSERT_TRUE(decode_key_values(f.data, kv));
  ASSERT_EQ(kv.size(), 4u);
  StreamDestination d;
  ASSERT_TRUE(read_destination(kv[1], d));
  EXPECT_EQ(format_ipv4(d.host_ip), "192.168.1.5");
  EXPECT_EQ(d.host_port, 56301);
  EXPECT_EQ(d.lidar_port, 56300);
  EXPECT_FALSE(read_destination(kv[3], d));  // one byte is no destination
}

TEST(LivoxCommand, KeyValueListsThatRunPastTheirDataAreRefused) {
  std::vector<KeyValue> kv;
  EXPECT_FALSE(decode_key_values({}, kv));
  EXPECT_FALSE(decode_key_values({2, 0, 0, 0, 0x1A, 0, 1, 0, 1}, kv));        // 2 keys announced, 1 sent
  EXPECT_FALSE(decode_key_values({1, 0, 0, 0, 0x1A, 0, 5, 0, 1}, kv));        // length 5, 1 byte
  EXPECT_FALSE(decode_key_values({1, 0, 0, 0, 0x1A, 0, 1, 0, 1, 9}, kv));     // a byte left over
  EXPECT_TRUE(decode_key_values({1, 0, 0, 0, 0x1A, 0, 1, 0, 1}, kv));
  std::uint8_t ret = 9;
  std::uint16_t key = 9;
  EXPECT_TRUE(read_config_ack(config_ack_data(0x20, 0x0099), ret, key));
  EXPECT_EQ(ret, 0x20);
  EXPECT_EQ(key, 0x0099);
  EXPECT_FALSE(read_config_ack({0, 0}, ret, key));
  std::array<std::uint8_t, 4> ip{};
  EXPECT_FALSE(parse_ipv4("192.168.1", ip));
  EXPECT_FALSE(parse_ipv4("192.168.1.256", ip));
  EXPECT_FALSE(parse_ipv4("192.168.1.5x", ip));
  EXPECT_TRUE(parse_ipv4("10.0.0.1", ip));
}

TEST(LivoxCommand, FuzzSeedsWrittenWithPythonDecode) {
  // Written by Python (struct, zlib.crc32 and a bitwise CRC-16): independent of porter's code.
  const std::string dir = std::string(PORTER_SOURCE_DIR) + "/tests/fuzz/corpus/livox_command/";
  for (const char* name : {"host_config_request", "config_ack", "empty_inquiry"}) {
    std::ifstream f(dir + name, std::ios::binary);
    const Bytes b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    CommandFrame d;
    ASSERT_EQ(decode_command(b.data(), b.size(), d), CommandStatus::ok) << name;
  }
  std::ifstream f(dir + "host_config_request", std::ios::binary);
  const Bytes b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::array<std::uint8_t, 4> ip{};
  parse_ipv4("192.168.1.5", ip);
  EXPECT_EQ(b, encode_command(host_config_request(1, ip, 56201, 56301, 56401)));
}

}  // namespace
}  // namespace porter::livox
