// MID-360 packet decoding and encoding against hand-built datagrams.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "packet_bytes.hpp"
#include "porter/livox/crc.hpp"
#include "porter/livox/decoder.hpp"
#include "porter/livox/encoder.hpp"

namespace porter::livox {
namespace {

using test::Bytes;

/// A 96-point high-precision packet: point i at (i, -2i, 1000 + 3i) mm, reflectivity i, tag i%4.
Bytes high_precision_packet(std::uint64_t timestamp = 123456789012ULL) {
  Bytes b = test::header(36 + 96 * 14, 4750, 96, 7, 3, 1, 0, timestamp);
  for (int i = 0; i < 96; ++i) {
    test::put_le(b, static_cast<std::uint32_t>(i), 4);
    test::put_le(b, static_cast<std::uint32_t>(-2 * i), 4);
    test::put_le(b, static_cast<std::uint32_t>(1000 + 3 * i), 4);
    b.push_back(static_cast<std::uint8_t>(i));
    b.push_back(static_cast<std::uint8_t>(i % 4));
  }
  test::finish(b);
  return b;
}

/// A 96-point low-precision packet: point i at (i, -i, 327) cm.
Bytes low_precision_packet() {
  Bytes b = test::header(36 + 96 * 8, 4750, 96, 0, 0, 2, 1, 5000000000ULL);
  for (int i = 0; i < 96; ++i) {
    test::put_le(b, static_cast<std::uint16_t>(i), 2);
    test::put_le(b, static_cast<std::uint16_t>(-i), 2);
    test::put_le(b, static_cast<std::uint16_t>(327), 2);
    b.push_back(200);
    b.push_back(0x15);
  }
  test::finish(b);
  return b;
}

Bytes imu_packet(float gx = 0.01f, float az = 1.0f) {
  Bytes b = test::header(36 + 24, 0, 1, 42, 0, 0, 0, 777000ULL);
  test::put_float(b, gx);
  test::put_float(b, -0.02f);
  test::put_float(b, 0.5f);
  test::put_float(b, 0.001f);
  test::put_float(b, -0.002f);
  test::put_float(b, az);
  test::finish(b);
  return b;
}

DecodeStatus decode(const Bytes& b, DecodedPacket& out, bool check_crc = true) {
  DecodeOptions o;
  o.check_crc = check_crc;
  return decode_packet(b.data(), b.size(), o, out);
}

TEST(LivoxCrc, CheckValuesOfTheProtocolsAlgorithms) {
  const char* s = "123456789";
  const auto* p = reinterpret_cast<const std::uint8_t*>(s);
  EXPECT_EQ(crc32(p, 9), 0xCBF43926u);
  EXPECT_EQ(crc16_ccitt_false(p, 9), 0x29B1u);
  EXPECT_EQ(crc32(p, 0), 0u);
}

TEST(LivoxCrc, TableCrcsMatchTheBitwiseReferenceOnRandomData) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    Bytes b(rng() % 1500);
    for (auto& x : b) x = static_cast<std::uint8_t>(rng());
    EXPECT_EQ(crc32(b.data(), b.size()), test::crc32_bitwise(b.data(), b.size()));
    EXPECT_EQ(crc16_ccitt_false(b.data(), b.size()), test::crc16_bitwise(b.data(), b.size()));
    // Continuing a CRC over a split buffer gives the CRC of the whole.
    const std::size_t cut = b.empty() ? 0 : rng() % b.size();
    EXPECT_EQ(crc32(b.data() + cut, b.size() - cut, crc32(b.data(), cut)), crc32(b.data(), b.size()));
  }
}

TEST(LivoxDecode, HighPrecisionPacketFieldsAndPoints) {
  const Bytes b = high_precision_packet();
  ASSERT_EQ(b.size(), 1380u);
  DecodedPacket d;
  ASSERT_EQ(decode(b, d), DecodeStatus::ok);
  EXPECT_EQ(d.header.version, 0);
  EXPECT_EQ(d.header.length, 1380);
  EXPECT_EQ(d.header.time_interval_100ns, 4750);
  EXPECT_EQ(d.header.dot_num, 96);
  EXPECT_EQ(d.header.udp_cnt, 7);
  EXPECT_EQ(d.header.frame_cnt, 3);
  EXPECT_EQ(d.header.data_type, 1);
  EXPECT_EQ(d.header.time_type, 0);
  EXPECT_EQ(d.header.timestamp_ns, 123456789012ULL);
  EXPECT_FALSE(d.is_imu());
  ASSERT_EQ(d.num_points, 96u);
  for (int i = 0; i < 96; ++i) {
    EXPECT_FLOAT_EQ(d.points[i].x_m, i * 1e-3f);
    EXPECT_FLOAT_EQ(d.points[i].y_m, -2 * i * 1e-3f);
    EXPECT_FLOAT_EQ(d.points[i].z_m, (1000 + 3 * i) * 1e-3f);
    EXPECT_EQ(d.points[i].reflectivity, i);
    EXPECT_EQ(d.points[i].tag, i % 4);
  }
  EXPECT_TRUE(d.points[0].is_no_return() == false);
  // 95 intervals over 475 us: 5 us apart.
  EXPECT_EQ(d.sample_offset_ns(0), 0);
  EXPECT_EQ(d.sample_offset_ns(1), 5000);
  EXPECT_EQ(d.sample_offset_ns(95), 475000);
}

TEST(LivoxDecode, LowPrecisionPacketIsInCentimetres) {
  const Bytes b = low_precision_packet();
  ASSERT_EQ(b.size(), 36u + 768u);
  DecodedPacket d;
  ASSERT_EQ(decode(b, d), DecodeStatus::ok);
  EXPECT_EQ(d.header.time_type, 1);
  ASSERT_EQ(d.num_points, 96u);
  EXPECT_FLOAT_EQ(d.points[5].x_m, 0.05f);
  EXPECT_FLOAT_EQ(d.points[5].y_m, -0.05f);
  EXPECT_FLOAT_EQ(d.points[5].z_m, 3.27f);
  EXPECT_EQ(d.points[5].reflectivity, 200);
  EXPECT_EQ(d.points[5].tag, 0x15);
}

TEST(LivoxDecode, ImuPacketInRadiansPerSecondAndG) {
  const Bytes b = imu_packet();
  ASSERT_EQ(b.size(), 60u);
  DecodedPacket d;
  ASSERT_EQ(decode(b, d), DecodeStatus::ok);
  EXPECT_TRUE(d.is_imu());
  EXPECT_EQ(d.num_points, 0u);
  EXPECT_EQ(d.header.udp_cnt, 42);
  EXPECT_FLOAT_EQ(d.imu.gyro_radps[0], 0.01f);
  EXPECT_FLOAT_EQ(d.imu.gyro_radps[1], -0.02f);
  EXPECT_FLOAT_EQ(d.imu.gyro_radps[2], 0.5f);
  EXPECT_FLOAT_EQ(d.imu.accel_g[0], 0.001f);
  EXPECT_FLOAT_EQ(d.imu.accel_g[1], -0.002f);
  EXPECT_FLOAT_EQ(d.imu.accel_g[2], 1.0f);
}

TEST(LivoxDecode, SphericalPacketBecomesCartesian) {
  Bytes b = test::header(36 + 2 * 10, 50, 2, 0, 0, 3, 0, 1);
  // depth 2000 mm, zenith 90 deg, azimuth 90 deg -> (0, 2, 0); depth 0 -> no return.
  test::put_le(b, 2000, 4);
  test::put_le(b, 9000, 2);
  test::put_le(b, 9000, 2);
  b.push_back(10);
  b.push_back(0);
  test::put_le(b, 0, 4);
  test::put_le(b, 0, 2);
  test::put_le(b, 0, 2);
  b.push_back(0);
  b.push_back(0);
  test::finish(b);
  DecodedPacket d;
  ASSERT_EQ(decode(b, d), DecodeStatus::ok);
  ASSERT_EQ(d.num_points, 2u);
  EXPECT_NEAR(d.points[0].x_m, 0.0f, 1e-6f);
  EXPECT_NEAR(d.points[0].y_m, 2.0f, 1e-6f);
  EXPECT_NEAR(d.points[0].z_m, 0.0f, 1e-6f);
  EXPECT_TRUE(d.points[1].is_no_return());
}

TEST(LivoxDecode, EveryTruncationIsRejectedWithoutReadingPastTheEnd) {
  for (const Bytes& full : {high_precision_packet(), low_precision_packet(), imu_packet()}) {
    for (std::size_t n = 0; n < full.size(); ++n) {
      // An exact-size heap copy, so a read past the end would be a read past the allocation.
      std::vector<std::uint8_t> cut(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
      DecodedPacket d;
      const DecodeStatus s = decode_packet(cut.data(), cut.size(), {}, d);
      EXPECT_EQ(s, n < 36 ? DecodeStatus::too_short : DecodeStatus::length_mismatch) << n;
    }
  }
}

TEST(LivoxDecode, OversizedDatagramsAreRejected) {
  Bytes b = high_precision_packet();
  b.push_back(0);
  DecodedPacket d;
  EXPECT_EQ(decode(b, d), DecodeStatus::length_mismatch);
  // Even when the length field is made to agree, 97 bytes of points are not 96 x 14.
  b[1] = static_cast<std::uint8_t>(b.size() & 0xFF);
  b[2] = static_cast<std::uint8_t>(b.size() >> 8);
  test::finish(b);
  EXPECT_EQ(decode(b, d), DecodeStatus::size_mismatch);
}

TEST(LivoxDecode, EachMalformedHeaderFieldHasItsReason) {
  DecodedPacket d;
  {
    Bytes b = high_precision_packet();
    b[0] = 1;
    EXPECT_EQ(decode(b, d), DecodeStatus::bad_version);
  }
  {
    Bytes b = high_precision_packet();
    b[10] = 4;  // data_type
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::unknown_data_type);
    b[10] = 0x11;  // dual-echo type of other Livox sensors: not a MID-360 type
    EXPECT_EQ(decode(b, d), DecodeStatus::unknown_data_type);
  }
  for (std::uint16_t dots : {0, 97, 1000}) {
    Bytes b = high_precision_packet();
    b[5] = static_cast<std::uint8_t>(dots & 0xFF);
    b[6] = static_cast<std::uint8_t>(dots >> 8);
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::bad_dot_num) << dots;
  }
  {
    Bytes b = high_precision_packet();
    b[5] = 95;  // 95 points announced, 96 sent
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::size_mismatch);
  }
  {
    Bytes b = imu_packet();
    b[5] = 2;  // an IMU packet carries one sample
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::bad_dot_num);
  }
  {
    Bytes b = imu_packet();
    b[10] = 1;  // 60 bytes cannot be one 14-byte point
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::size_mismatch);
  }
  {
    Bytes b = high_precision_packet();
    b[11] = 3;
    test::finish(b);
    EXPECT_EQ(decode(b, d), DecodeStatus::unknown_time_type);
  }
}

TEST(LivoxDecode, CrcCoversTimestampAndDataButNotTheHeaderBeforeIt) {
  DecodedPacket d;
  for (std::size_t at : {28u, 35u, 36u, 700u, 1379u}) {
    Bytes b = high_precision_packet();
    b[at] ^= 0x40;
    EXPECT_EQ(decode(b, d), DecodeStatus::crc_mismatch) << at;
    EXPECT_EQ(decode(b, d, /*check_crc=*/false), DecodeStatus::ok) << at;
  }
  Bytes b = high_precision_packet();
  b[24] ^= 1;  // the CRC field itself
  EXPECT_EQ(decode(b, d), DecodeStatus::crc_mismatch);
  Bytes r = high_precision_packet();
  r[12] = 0xAA;  // reserved bytes are outside the CRC
  EXPECT_EQ(decode(r, d), DecodeStatus::ok);
}

TEST(LivoxDecode, NonFiniteImuAndOutOfRangeAnglesAreBadValues) {
  DecodedPacket d;
  EXPECT_EQ(decode(imu_packet(std::numeric_limits<float>::quiet_NaN()), d), DecodeStatus::bad_value);
  EXPECT_EQ(decode(imu_packet(0.0f, std::numeric_limits<float>::infinity()), d), DecodeStatus::bad_value);
  Bytes b = test::header(36 + 10, 0, 1, 0, 0, 3, 0, 1);
  test::put_le(b, 1000, 4);
  test::put_le(b, 18001, 2);  // zenith beyond 180 deg
  test::put_le(b, 0, 2);
  b.push_back(0);
  b.push_back(0);
  test::finish(b);
  EXPECT_EQ(decode(b, d), DecodeStatus::bad_value);
}

TEST(LivoxDecode, CountersTallyByReason) {
  DecodeCounters c;
  c.add(DecodeStatus::ok);
  c.add(DecodeStatus::crc_mismatch);
  c.add(DecodeStatus::crc_mismatch);
  c.add(DecodeStatus::too_short);
  EXPECT_EQ(c.total(), 4u);
  EXPECT_EQ(c.malformed(), 3u);
  EXPECT_EQ(c.count(DecodeStatus::crc_mismatch), 2u);
  EXPECT_EQ(c.summary(), "too_short=1 crc_mismatch=2");
  EXPECT_EQ(DecodeCounters().summary(), "");
}

TEST(LivoxDecode, FuzzSeedsWrittenWithPythonsZlibDecode) {
  // The seeds were written by Python (struct + zlib.crc32): a third CRC-32 implementation.
  const std::string dir = std::string(PORTER_SOURCE_DIR) + "/tests/fuzz/corpus/livox_packet/";
  for (const char* name : {"cartesian_high", "cartesian_low", "spherical", "imu", "two_points"}) {
    std::ifstream f(dir + name, std::ios::binary);
    const Bytes b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(b.empty()) << name;
    DecodedPacket d;
    EXPECT_EQ(decode(b, d), DecodeStatus::ok) << name;
  }
}

TEST(LivoxEncode, EncoderWritesTheHandBuiltBytes) {
  const Bytes expected = high_precision_packet(99);
  std::array<Point, 96> pts;
  for (int i = 0; i < 96; ++i) {
    pts[i].x_m = i * 1e-3f;
    pts[i].y_m = -2 * i * 1e-3f;
    pts[i].z_m = (1000 + 3 * i) * 1e-3f;
    pts[i].reflectivity = static_cast<std::uint8_t>(i);
    pts[i].tag = static_cast<std::uint8_t>(i % 4);
  }
  PacketInfo info;
  info.time_interval_100ns = 4750;
  info.udp_cnt = 7;
  info.frame_cnt = 3;
  info.timestamp_ns = 99;
  std::array<std::uint8_t, kMaxPacketSize> out{};
  ASSERT_EQ(encode_point_packet(info, DataType::kCartesianHigh, pts.data(), 96, out.data(), out.size()), 1380u);
  EXPECT_EQ(Bytes(out.begin(), out.begin() + 1380), expected);

  ImuSample s;
  s.gyro_radps = {0.01f, -0.02f, 0.5f};
  s.accel_g = {0.001f, -0.002f, 1.0f};
  PacketInfo imu_info;
  imu_info.udp_cnt = 42;
  imu_info.timestamp_ns = 777000;
  ASSERT_EQ(encode_imu_packet(imu_info, s, out.data(), out.size()), 60u);
  EXPECT_EQ(Bytes(out.begin(), out.begin() + 60), imu_packet());
}

TEST(LivoxEncode, RoundTripRoundsToTheUnitAndClamps) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  for (DataType type : {DataType::kCartesianHigh, DataType::kCartesianLow, DataType::kSpherical}) {
    std::array<Point, 96> pts;
    for (auto& p : pts) p = {u(rng), u(rng), u(rng), 9, 1};
    pts[3] = Point{};                     // no return stays no return
    pts[4] = {1000.0f, -1000.0f, 0.5f, 1, 0};  // beyond int16 centimetres
    PacketInfo info;
    std::array<std::uint8_t, kMaxPacketSize> out{};
    const std::size_t n = encode_point_packet(info, type, pts.data(), 96, out.data(), out.size());
    ASSERT_EQ(n, packet_size(type, 96));
    DecodedPacket d;
    ASSERT_EQ(decode_packet(out.data(), n, {}, d), DecodeStatus::ok);
    const float unit = type == DataType::kCartesianLow ? 0.01f : 0.001f;
    for (int i = 0; i < 96; ++i) {
      if (i == 4) continue;
      // Spherical: depth to 1 mm and angles to 0.01 deg (1.2 cm at 87 m).
      const float tol = type == DataType::kSpherical ? 0.0015f + 87.0f * 1.75e-4f / 2.0f : 0.5f * unit + 1e-5f;
      EXPECT_NEAR(d.points[i].x_m, pts[i].x_m, tol);
      EXPECT_NEAR(d.points[i].y_m, pts[i].y_m, tol);
      EXPECT_NEAR(d.points[i].z_m, pts[i].z_m, tol);
    }
    EXPECT_TRUE(d.points[3].is_no_return());
    if (type == DataType::kCartesianLow) {
      EXPECT_FLOAT_EQ(d.points[4].x_m, 327.67f);
      EXPECT_FLOAT_EQ(d.points[4].y_m, -327.68f);
    } else {
      EXPECT_NEAR(d.points[4].x_m, 1000.0f, 0.1f);
    }
  }
}

TEST(LivoxEncode, RefusesBadCountsTypesAndSmallBuffers) {
  std::array<Point, 97> pts{};
  std::array<std::uint8_t, kMaxPacketSize + 14> out{};
  PacketInfo info;
  EXPECT_EQ(encode_point_packet(info, DataType::kCartesianHigh, pts.data(), 0, out.data(), out.size()), 0u);
  EXPECT_EQ(encode_point_packet(info, DataType::kCartesianHigh, pts.data(), 97, out.data(), out.size()), 0u);
  EXPECT_EQ(encode_point_packet(info, DataType::kImu, pts.data(), 1, out.data(), out.size()), 0u);
  EXPECT_EQ(encode_point_packet(info, DataType::kCartesianHigh, pts.data(), 96, out.data(), 1379), 0u);
  EXPECT_EQ(encode_imu_packet(info, ImuSample{}, out.data(), 59), 0u);
}

}  // namespace
}  // namespace porter::livox
