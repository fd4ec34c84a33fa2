// Host-clock mapping, cloud assembly and the driver's stream handling (no sockets).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "porter/livox/cloud_assembler.hpp"
#include "porter/livox/encoder.hpp"
#include "porter/livox/host_time.hpp"
#include "porter/livox/lidar_stream.hpp"

namespace porter::livox {
namespace {

std::int64_t llabs64(std::int64_t v) { return v < 0 ? -v : v; }

constexpr std::int64_t kSpanNs = 475000;     // 95 x 5 us
constexpr std::int64_t kPacketNs = 480000;   // 96 x 5 us

/// A decoded 96-point packet; point i at (i + 1, 0, 0) m unless listed in `no_return`.
DecodedPacket packet(std::uint64_t timestamp_ns, std::vector<int> no_return = {}) {
  DecodedPacket d;
  d.header.dot_num = 96;
  d.header.data_type = 1;
  d.header.time_interval_100ns = static_cast<std::uint16_t>(kSpanNs / 100);
  d.header.timestamp_ns = timestamp_ns;
  d.num_points = 96;
  for (int i = 0; i < 96; ++i) d.points[i] = {static_cast<float>(i + 1), 0.0f, 0.0f, 50, 0};
  for (int i : no_return) d.points[i] = Point{};
  return d;
}

/// Encoded bytes of a point packet at sensor time t (all points at (1, 2, 3) m).
std::vector<std::uint8_t> point_bytes(std::uint64_t t_ns, TimeType type = TimeType::kNoSync) {
  std::array<Point, 96> pts;
  pts.fill({1.0f, 2.0f, 3.0f, 10, 0});
  PacketInfo info;
  info.time_interval_100ns = kSpanNs / 100;
  info.time_type = type;
  info.timestamp_ns = t_ns;
  std::vector<std::uint8_t> b(kMaxPacketSize);
  b.resize(encode_point_packet(info, DataType::kCartesianHigh, pts.data(), 96, b.data(), b.size()));
  return b;
}

std::vector<std::uint8_t> imu_bytes(std::uint64_t t_ns, std::uint16_t cnt) {
  ImuSample s;
  s.gyro_radps = {0.0f, 0.0f, 0.25f};
  s.accel_g = {0.0f, 0.0f, 1.0f};
  PacketInfo info;
  info.udp_cnt = cnt;
  info.timestamp_ns = t_ns;
  std::vector<std::uint8_t> b(64);
  b.resize(encode_imu_packet(info, s, b.data(), b.size()));
  return b;
}

TEST(HostTimeMapper, MinimumFilterRemovesTransportJitter) {
  HostTimeMapper m({/*window_s=*/1.0, /*reset_threshold_s=*/0.5});
  std::mt19937_64 rng(1);
  std::exponential_distribution<double> delay_us(1.0 / 300.0);  // mean 0.3 ms of extra delay
  const std::int64_t host_at_sensor_zero = 1'700'000'000'000'000'000LL;
  const std::int64_t base_delay = 150000;  // 150 us minimum transport delay
  std::int64_t worst = 0;
  for (int j = 0; j < 5000; ++j) {
    const std::int64_t sensor = 10'000'000'000LL + j * kPacketNs;
    const std::int64_t sent_host = host_at_sensor_zero + sensor + kSpanNs;
    const auto extra = static_cast<std::int64_t>(delay_us(rng) * 1000.0);
    const std::int64_t mapped = m.map(static_cast<std::uint64_t>(sensor), kSpanNs, sent_host + base_delay + extra);
    const std::int64_t truth = host_at_sensor_zero + sensor;
    if (j >= 100) worst = std::max(worst, llabs64(mapped - truth - base_delay));
  }
  // After a few packets the least-delayed one sets the offset: mapped = truth + minimum delay.
  EXPECT_LT(worst, 5000);  // within 5 us, against a jitter of ~0.3 ms mean
  EXPECT_EQ(m.resets(), 0u);
}

TEST(HostTimeMapper, FollowsClockDriftAndRestartsAfterASensorReboot) {
  HostTimeMapper m({0.5, 0.5});
  const double drift = 100e-6;  // sensor clock 100 ppm slow
  std::int64_t max_err = 0;
  for (int j = 0; j < 20000; ++j) {  // 9.6 s
    const std::int64_t sensor = j * kPacketNs;
    const auto host = static_cast<std::int64_t>(sensor * (1.0 + drift)) + kSpanNs + 200000;
    const std::int64_t mapped = m.map(static_cast<std::uint64_t>(sensor), kSpanNs, host);
    // Mapped = true time + the 200 us delay, late by the window's lag on the drift.
    const auto truth = static_cast<std::int64_t>(sensor * (1.0 + drift));
    if (j > 10) max_err = std::max(max_err, llabs64(mapped - truth - 200000));
  }
  // The window lags the drift by at most 2 x 0.5 s x 100 ppm = 100 us.
  EXPECT_LT(max_err, 110000);
  EXPECT_EQ(m.resets(), 0u);
  // Reboot: the sensor clock restarts at 0 while the host clock goes on.
  const std::int64_t host = 20'000'000'000LL;
  const std::int64_t mapped = m.map(1000, kSpanNs, host);
  EXPECT_EQ(m.resets(), 1u);
  EXPECT_EQ(mapped, host - kSpanNs);
}

TEST(HostTimeMapper, WindowZeroIsEachPacketsOwnReceiveTimeAndSmallStepsBackAreClamped) {
  HostTimeMapper m({/*window_s=*/0.0, /*reset_threshold_s=*/0.5, /*max_clamp_s=*/100e-6});
  const std::int64_t r0 = 5'000'000'000LL;
  const std::uint64_t s0 = 1'000'000;
  EXPECT_EQ(m.map(s0, kSpanNs, r0), r0 - kSpanNs);
  // Received 50 us "early": its first sample would precede the previous packet's last by
  // 45 us, so it is moved to it.
  EXPECT_EQ(m.map(s0 + kPacketNs, kSpanNs, r0 + kPacketNs - 50000), r0);
  EXPECT_EQ(m.clamped(), 1u);
  // 400 us early: a step back of 390 us is taken as it is.
  EXPECT_EQ(m.map(s0 + 2 * kPacketNs, kSpanNs, r0 + 2 * kPacketNs - 400000), r0 + 2 * kPacketNs - 400000 - kSpanNs);
  EXPECT_EQ(m.clamped(), 1u);
  EXPECT_EQ(m.steps_back(), 1u);
  // The IMU stream has its own clamp: an IMU sample older than the points is not moved.
  EXPECT_EQ(m.map(s0, 0, r0, /*stream=*/1), r0);
  EXPECT_EQ(m.clamped(), 1u);
}

TEST(CloudAssembler, CutsAtPeriodBoundariesWithPerPointTimes) {
  CloudAssemblerParams p;
  p.period_s = 0.1;
  CloudAssembler a(p);
  std::vector<Cloud> done;
  // 0.25 s of packets starting at t = 0.05 s.
  const std::int64_t t0 = 50'000'000;
  std::size_t points = 0;
  for (int j = 0; j < 520; ++j) {  // the last point at 0.2996 s
    a.add(packet(0), t0 + j * kPacketNs, done);
    points += 96;
  }
  ASSERT_EQ(done.size(), 2u);
  // Cloud 0: points with t in [0.05, 0.1): 0.05 s / 5 us = 10,000 points.
  EXPECT_EQ(done[0].size(), 10000u);
  EXPECT_EQ(done[0].start_ns, t0);
  EXPECT_EQ(done[0].scan_id, 0);
  EXPECT_EQ(done[1].size(), 20000u);
  EXPECT_EQ(done[1].start_ns, 100'000'000);
  EXPECT_EQ(done[1].scan_id, 1);
  for (const Cloud& c : done) {
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_EQ(c.time_offset_ns[i], static_cast<std::int32_t>(5000 * i));
      EXPECT_EQ(c.line[i], (i + (c.start_ns == t0 ? 0 : 10000)) % 4);
    }
  }
  std::vector<Cloud> rest;
  EXPECT_TRUE(a.flush(rest));
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_EQ(done[0].size() + done[1].size() + rest[0].size(), points);
  EXPECT_FALSE(a.flush(rest));
}

TEST(CloudAssembler, AppliesTheExtrinsicAndDropsOrKeepsNoReturns) {
  CloudAssemblerParams p;
  p.T_out_sensor = Eigen::Isometry3d::Identity();
  p.T_out_sensor.translation() = Eigen::Vector3d(-0.22, 0.0, 0.5325);
  p.T_out_sensor.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  CloudAssembler a(p);
  std::vector<Cloud> done;
  a.add(packet(0, {0, 5, 95}), 0, done);
  a.flush(done);
  ASSERT_EQ(done.size(), 1u);
  ASSERT_EQ(done[0].size(), 93u);
  EXPECT_EQ(a.no_return_points(), 3u);
  // Point 1 is (2, 0, 0) in the sensor: rotated to (0, 2, 0), then translated.
  EXPECT_NEAR(done[0].x_m[0], -0.22f, 1e-6f);
  EXPECT_NEAR(done[0].y_m[0], 2.0f, 1e-6f);
  EXPECT_NEAR(done[0].z_m[0], 0.5325f, 1e-6f);
  EXPECT_EQ(done[0].time_offset_ns[0], 0);       // the first kept point starts the cloud
  EXPECT_EQ(done[0].line[0], 1);                 // line from the sample index, 1 % 4

  p.keep_no_return = true;
  CloudAssembler keep(p);
  std::vector<Cloud> kept;
  keep.add(packet(0, {0}), 0, kept);
  keep.flush(kept);
  EXPECT_EQ(kept[0].size(), 96u);
}

TEST(CloudAssembler, BoundsMemoryAndSplitsOnAClockStepBack) {
  CloudAssemblerParams p;
  p.max_points = 100;
  CloudAssembler a(p);
  std::vector<Cloud> done;
  a.add(packet(0), 1'000'000'000, done);
  a.add(packet(0), 1'000'480'000, done);
  EXPECT_TRUE(done.empty());
  EXPECT_EQ(a.points_over_capacity(), 92u);
  // The clock steps back by 10 ms inside the same period.
  a.add(packet(0), 990'000'000, done);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].size(), 100u);
  EXPECT_EQ(a.time_steps(), 1u);
}

TEST(LidarStream, HostClockCloudsLossCountsAndImu) {
  LidarStreamParams p;
  p.host_time.window_s = 1.0;
  LidarStream s(p);
  std::vector<Cloud> clouds;
  std::vector<ImuMeasurement> imu;
  const std::int64_t host0 = 1'700'000'000'000'000'000LL;
  int sent = 0;
  for (int j = 0; j < 600; ++j) {
    if (j == 100 || j == 101 || j == 300) continue;  // three packets lost
    const std::int64_t t = j * kPacketNs;
    const auto b = point_bytes(static_cast<std::uint64_t>(t));
    s.handle(b.data(), b.size(), false, host0 + t + kSpanNs + 100000, clouds, imu);
    ++sent;
  }
  EXPECT_EQ(s.counters().point_packets, static_cast<std::uint64_t>(sent));
  EXPECT_EQ(s.counters().lost_point_packets, 3u);
  EXPECT_EQ(s.counters().decode.malformed(), 0u);
  ASSERT_GE(clouds.size(), 2u);
  // Output times are on the host clock: sensor time + (minimum) delay 100 us.
  EXPECT_EQ(clouds[0].start_ns, host0 + 100000);
  EXPECT_EQ(clouds[1].start_ns % 100'000'000, 0);

  for (std::uint16_t k : {0, 1, 2, 5}) {  // 3 and 4 lost
    const auto b = imu_bytes(k * 5'000'000ULL, k);
    s.handle(b.data(), b.size(), false, host0 + k * 5'000'000LL + 100000, clouds, imu);
  }
  ASSERT_EQ(imu.size(), 4u);
  EXPECT_EQ(s.counters().lost_imu_packets, 2u);
  EXPECT_FLOAT_EQ(imu[0].sample.accel_g[2], 1.0f);
  EXPECT_EQ(imu[3].time_ns, host0 + 25'000'000 + 100000);

  // Malformed and truncated datagrams are counted by reason and change nothing else.
  auto bad = point_bytes(0);
  bad[40] ^= 1;
  s.handle(bad.data(), bad.size(), false, host0, clouds, imu);
  s.handle(bad.data(), 10, false, host0, clouds, imu);
  s.handle(bad.data(), bad.size(), true, host0, clouds, imu);
  EXPECT_EQ(s.counters().decode.count(DecodeStatus::crc_mismatch), 1u);
  EXPECT_EQ(s.counters().decode.count(DecodeStatus::too_short), 1u);
  EXPECT_EQ(s.counters().decode.count(DecodeStatus::length_mismatch), 1u);
  EXPECT_NE(s.summary().find("crc_mismatch=1"), std::string::npos);
  EXPECT_NE(s.summary().find("lost 3 point + 2 imu"), std::string::npos);
}

TEST(LidarStream, SynchronisedTimeIsUsedAsSentAndIdleStreamsFlush) {
  LidarStream s({});
  std::vector<Cloud> clouds;
  std::vector<ImuMeasurement> imu;
  const std::uint64_t ptp = 1'700'000'000'123'000'000ULL;
  const auto b = point_bytes(ptp, TimeType::kPtp);
  s.handle(b.data(), b.size(), false, 42, clouds, imu);  // receive time is ignored
  EXPECT_TRUE(clouds.empty());
  EXPECT_FALSE(s.flush_if_idle(42 + 500'000'000, 1.0, clouds));
  EXPECT_TRUE(s.flush_if_idle(42 + 1'000'000'000, 1.0, clouds));
  ASSERT_EQ(clouds.size(), 1u);
  EXPECT_EQ(clouds[0].start_ns, static_cast<std::int64_t>(ptp));
  EXPECT_EQ(clouds[0].time_type, 1);
  EXPECT_EQ(clouds[0].size(), 96u);
}

}  // namespace
}  // namespace porter::livox
