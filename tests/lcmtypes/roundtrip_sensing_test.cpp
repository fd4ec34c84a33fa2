// Round trips of the sensing, map, CAN and supervision types: every field must survive.

#include <gtest/gtest.h>

#include <cstdint>

#include "porter/can_frame_t.hpp"
#include "porter/estop_t.hpp"
#include "porter/imu_t.hpp"
#include "porter/octomap_t.hpp"
#include "porter/point_cloud_t.hpp"
#include "porter/process_heartbeat_t.hpp"
#include "roundtrip_support.hpp"

namespace porter {
namespace {

using test::expect_rejects;
using test::roundtrip;

TEST(LcmRoundTrip, PointCloud) {
  point_cloud_t m{};
  m.utime = 1'699'999'999'000'000;
  m.frame_id = "lidar";
  m.scan_id = 1234;
  m.num_points = 500;
  for (int i = 0; i < m.num_points; ++i) {
    m.x_m.push_back(0.01f * static_cast<float>(i) - 2.0f);
    m.y_m.push_back(-0.02f * static_cast<float>(i) + 1.0f);
    m.z_m.push_back(0.001f * static_cast<float>(i % 97));
    m.intensity.push_back(static_cast<float>(i % 256));
    m.time_offset_ns.push_back(200 * i);
    m.line.push_back(static_cast<std::uint8_t>(i % 4));
    m.tag.push_back(static_cast<std::uint8_t>((i * 7) % 256));
  }
  const point_cloud_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.scan_id, m.scan_id);
  EXPECT_EQ(r.num_points, m.num_points);
  EXPECT_EQ(r.x_m, m.x_m);
  EXPECT_EQ(r.y_m, m.y_m);
  EXPECT_EQ(r.z_m, m.z_m);
  EXPECT_EQ(r.intensity, m.intensity);
  EXPECT_EQ(r.time_offset_ns, m.time_offset_ns);
  EXPECT_EQ(r.line, m.line);
  EXPECT_EQ(r.tag, m.tag);
  expect_rejects(m, imu_t{});
}

TEST(LcmRoundTrip, Imu) {
  imu_t m{};
  m.utime = 42'000'123;
  m.frame_id = "lidar_imu";
  m.gyro_x_radps = 0.011;
  m.gyro_y_radps = -0.022;
  m.gyro_z_radps = 0.5;
  m.accel_x_mps2 = 0.12;
  m.accel_y_mps2 = -0.34;
  m.accel_z_mps2 = 9.80665;
  const imu_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.gyro_x_radps, m.gyro_x_radps);
  EXPECT_EQ(r.gyro_y_radps, m.gyro_y_radps);
  EXPECT_EQ(r.gyro_z_radps, m.gyro_z_radps);
  EXPECT_EQ(r.accel_x_mps2, m.accel_x_mps2);
  EXPECT_EQ(r.accel_y_mps2, m.accel_y_mps2);
  EXPECT_EQ(r.accel_z_mps2, m.accel_z_mps2);
  expect_rejects(m, estop_t{});
}

TEST(LcmRoundTrip, Octomap) {
  octomap_t m{};
  m.utime = 88'888'888;
  m.frame_id = "world";
  m.map_id = 17;
  m.resolution_m = 0.05;
  m.binary = true;
  m.tree_type = "OcTree";
  m.num_bytes = 4096;
  for (int i = 0; i < m.num_bytes; ++i) m.data.push_back(static_cast<std::uint8_t>((i * 31) ^ 0x5a));
  const octomap_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.frame_id, m.frame_id);
  EXPECT_EQ(r.map_id, m.map_id);
  EXPECT_EQ(r.resolution_m, m.resolution_m);
  EXPECT_EQ(r.binary, m.binary);
  EXPECT_EQ(r.tree_type, m.tree_type);
  EXPECT_EQ(r.num_bytes, m.num_bytes);
  EXPECT_EQ(r.data, m.data);
  expect_rejects(m, point_cloud_t{});
}

TEST(LcmRoundTrip, CanFrame) {
  can_frame_t m{};
  m.utime = 66'000'000;
  m.bus = "base";
  m.sender = "porter-base";
  m.id = 0x111;
  m.extended = false;
  m.rtr = false;
  m.dlc = 8;
  m.data = {0x00, 0x96, 0x00, 0x32, 0x00, 0x00, 0xff, 0x80};
  const can_frame_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.bus, m.bus);
  EXPECT_EQ(r.sender, m.sender);
  EXPECT_EQ(r.id, m.id);
  EXPECT_EQ(r.extended, m.extended);
  EXPECT_EQ(r.rtr, m.rtr);
  EXPECT_EQ(r.dlc, m.dlc);
  EXPECT_EQ(r.data, m.data);
  expect_rejects(m, estop_t{});
}

TEST(LcmRoundTrip, CanFrameExtendedRtr) {
  can_frame_t m{};
  m.utime = 1;
  m.bus = "arm";
  m.sender = "porter-sim";
  m.id = 0x1abcdef0;
  m.extended = true;
  m.rtr = true;
  m.dlc = 0;
  const can_frame_t r = roundtrip(m);
  EXPECT_EQ(r.id, m.id);
  EXPECT_TRUE(r.extended);
  EXPECT_TRUE(r.rtr);
  EXPECT_EQ(r.dlc, 0);
  EXPECT_TRUE(r.data.empty());
  EXPECT_EQ(r.sender, m.sender);
}

TEST(LcmRoundTrip, Estop) {
  estop_t m{};
  m.utime = 3'000'000;
  m.active = true;
  m.source = "operator";
  m.reason = "person in the workspace";
  const estop_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.active, m.active);
  EXPECT_EQ(r.source, m.source);
  EXPECT_EQ(r.reason, m.reason);
  expect_rejects(m, can_frame_t{});
}

TEST(LcmRoundTrip, ProcessHeartbeat) {
  process_heartbeat_t m{};
  m.utime = 9'000'000'000;
  m.process = "porter-tracker";
  m.host = "porter-nuc";
  m.pid = 31337;
  m.start_utime = 8'000'000'000;
  m.health = process_heartbeat_t::HEALTH_WARN;
  m.status = "3 loop overruns";
  m.loop_rate_hz = 99.7;
  m.loop_overruns = 3;
  m.dropped_datagrams = 42;
  const process_heartbeat_t r = roundtrip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.process, m.process);
  EXPECT_EQ(r.host, m.host);
  EXPECT_EQ(r.pid, m.pid);
  EXPECT_EQ(r.start_utime, m.start_utime);
  EXPECT_EQ(r.health, m.health);
  EXPECT_EQ(r.status, m.status);
  EXPECT_EQ(r.loop_rate_hz, m.loop_rate_hz);
  EXPECT_EQ(r.loop_overruns, m.loop_overruns);
  EXPECT_EQ(r.dropped_datagrams, m.dropped_datagrams);
  expect_rejects(m, estop_t{});
}

}  // namespace
}  // namespace porter
