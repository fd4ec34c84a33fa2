// porter-mapper as a process: clouds and states over udpm (a private port) in, MAP_OCTOMAP and
// HEARTBEAT out; stopped by PID with SIGTERM.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "../drivers/livox/process_support.hpp"
#include "mapping_support.hpp"
#include "porter/lcm_bus.hpp"
#include "private_lcm_url.hpp"

namespace porter::mapping {
namespace {

using livox::sim::Waypoint;

/// The shipped mapper config on `url` with a 1 s status period, written next to it as
/// mapping/<prefix><pid>.yaml (its relative paths stay valid); returns the path.
std::string write_config(const std::string& url, const std::string& prefix) {
  std::ifstream in(test::config_path("mapping/porter_mapper.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string cfg = text.str();
  cfg.replace(cfg.find("lcm_url: \"\""), 11, "lcm_url: \"" + url + "\"");
  cfg.replace(cfg.find("status_log_period_s: 10.0"), 25, "status_log_period_s: 1.0");
  const std::string path = test::config_path("mapping/" + prefix + std::to_string(::getpid()) + ".yaml");
  { std::ofstream(path) << cfg; }
  return path;
}

TEST(MapperProcess, CloudsInMapsAndHeartbeatOut) {
  const std::string url = porter::test::private_lcm_url() + "&recv_buf_size=4194304";
  const std::string cfg_path = write_config(url, ".process_test_");
  const std::string log_path = ::testing::TempDir() + "porter_mapper_process_" + std::to_string(::getpid()) + ".log";

  porter::LcmBus bus(url);
  ASSERT_TRUE(bus.good());
  std::vector<porter::octomap_t> maps;
  std::string heartbeat;
  bus.subscribe(porter::channels::kMapOctomap, [&](const porter::octomap_t& m) { maps.push_back(m); });
  bus.subscribe(porter::channels::kHeartbeat, [&](const porter::process_heartbeat_t& h) {
    if (h.process == "porter-mapper") heartbeat = h.status;
  });
  livox::test::ChildProcess mapper(PORTER_MAPPER_BIN, {"--config", cfg_path}, log_path);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (heartbeat.empty() && std::chrono::steady_clock::now() < deadline && mapper.running()) bus.handle_timeout(100);
  std::remove(cfg_path.c_str());
  ASSERT_FALSE(heartbeat.empty()) << mapper.log();

  const app::MapperConfig shipped = test::shipped_config();
  const RobotModel robot = test::robot_with("long_bar");
  std::vector<CollisionShape> obstacles;
  CollisionShape post;
  post.geometry = Box{Eigen::Vector3d(0.3, 0.3, 1.2)};
  post.T_parent_shape.translation() = Eigen::Vector3d(-0.4, 2.0, 0.6);
  obstacles.push_back(post);
  test::SimDrive drive(robot, obstacles, {Waypoint{0.0, test::config_at(0, 0, 0)}, Waypoint{1.0, test::config_at(0.5, 0, 0)}},
                       shipped.mapper.T_B_S);
  StateBuffer unused;
  std::vector<std::pair<std::int64_t, RobotConfiguration>> states;
  std::size_t sent = 0;
  for (int k = 0; k < 10; ++k) {
    const test::SimCloud c = drive.next(unused, &states);
    for (; sent < states.size(); ++sent) {
      porter::robot_state_t s{};
      s.utime = states[sent].first;
      s.frame_id = "world";
      s.x_m = states[sent].second.base.x_m;
      s.y_m = states[sent].second.base.y_m;
      s.yaw_rad = states[sent].second.base.yaw_rad;
      s.num_joints = kNumArmJoints;
      s.q_rad.assign(states[sent].second.q_rad.data(), states[sent].second.q_rad.data() + kNumArmJoints);
      s.qd_radps.assign(kNumArmJoints, 0.0);
      bus.publish(porter::channels::kRobotState, s);
    }
    porter::point_cloud_t m{};
    m.utime = c.cloud.utime;
    m.frame_id = "lidar";
    m.scan_id = k;
    m.num_points = static_cast<std::int32_t>(c.cloud.size());
    m.x_m = c.cloud.x_m;
    m.y_m = c.cloud.y_m;
    m.z_m = c.cloud.z_m;
    m.intensity.assign(c.cloud.size(), 0.0f);
    m.time_offset_ns = c.cloud.time_offset_ns;
    m.line.assign(c.cloud.size(), 0);
    m.tag.assign(c.cloud.size(), 0);
    ASSERT_TRUE(bus.publish(porter::channels::kLidarPoints, m));
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
    while (std::chrono::steady_clock::now() < until) bus.handle_timeout(10);
  }
  // Every cloud is accounted for: processed, or dropped and counted (on a loaded machine the
  // mapper may be busy when one arrives).
  int processed = 0, received = 0, busy = 0, dropped = 0;
  const auto counts = [&] {
    return std::sscanf(heartbeat.c_str(), "clouds %d/%d, arrived while busy %d, dropped %d", &processed, &received, &busy,
                       &dropped) == 4;
  };
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (std::chrono::steady_clock::now() < end && !(counts() && processed + dropped == 10)) bus.handle_timeout(100);
  const int status = mapper.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << mapper.log();
  ASSERT_TRUE(counts()) << heartbeat;
  EXPECT_EQ(received, 10) << heartbeat << "\n" << mapper.log();
  EXPECT_EQ(processed + dropped, 10) << heartbeat;
  EXPECT_GE(busy, dropped);
  if (dropped > 0) {
    EXPECT_NE(mapper.log().find("clouds arrived while busy"), std::string::npos);
  }
  ASSERT_FALSE(maps.empty()) << mapper.log();
  const porter::octomap_t& last = maps.back();
  EXPECT_GT(last.num_bytes, 100);
  EXPECT_EQ(last.tree_type, "OcTree");
  // The robot pose at the map's time (the last map goes out with whichever cloud made it due).
  const double t_map = (last.utime - test::SimDrive::kEpochUs) * 1e-6;
  EXPECT_GT(t_map, 0.3);
  EXPECT_NEAR(last.robot_x_m, 0.5 * std::min(t_map, 1.0), 0.005);
  octomap::OcTree tree(last.resolution_m);
  std::istringstream s(std::string(last.data.begin(), last.data.end()));
  tree.readBinaryData(s);
  // The post's near face (y = 1.85 lies on a voxel face: its hits round to either side).
  int face = 0;
  for (double x = -0.525; x < -0.25; x += 0.05)
    for (double y : {1.825, 1.875}) {
      const octomap::OcTreeNode* n = tree.search(x, y, 0.625);
      face += n && tree.isNodeOccupied(n);
    }
  EXPECT_GE(face, 3);
  std::printf("%zu maps; heartbeat: %s\n", maps.size(), heartbeat.c_str());
  std::remove(log_path.c_str());
}

// A burst of clouds, as a replayed log delivers porter-sim's catch-up (22 clouds within 50 ms):
// every cloud reaches the node (LCM discards, uncounted, a message whose subscription queue is
// full), and each is processed or dropped and counted there.
TEST(MapperProcess, ABurstOfCloudsReachesTheNodeWhole) {
  const std::string url = porter::test::private_lcm_url() + "&recv_buf_size=4194304";
  const std::string cfg_path = write_config(url, ".process_burst_test_");
  const std::string log_path = ::testing::TempDir() + "porter_mapper_burst_" + std::to_string(::getpid()) + ".log";

  porter::LcmBus bus(url);
  ASSERT_TRUE(bus.good());
  std::string heartbeat;
  bus.subscribe(porter::channels::kHeartbeat, [&](const porter::process_heartbeat_t& h) {
    if (h.process == "porter-mapper") heartbeat = h.status;
  });
  livox::test::ChildProcess mapper(PORTER_MAPPER_BIN, {"--config", cfg_path}, log_path);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (heartbeat.empty() && std::chrono::steady_clock::now() < deadline && mapper.running()) bus.handle_timeout(100);
  std::remove(cfg_path.c_str());
  ASSERT_FALSE(heartbeat.empty()) << mapper.log();

  // Small clouds (1,000 points, ~22 kB: the burst stays far below the socket's receive buffer,
  // so only a queue inside the process can lose one), all sent while the mapper is stopped
  // (SIGSTOP, as when it does not get the CPU on a loaded machine): it finds them all at once.
  constexpr int kClouds = 40;
  ASSERT_EQ(::kill(mapper.pid(), SIGSTOP), 0);
  const std::int64_t t0 = test::SimDrive::kEpochUs;
  for (int k = 0; k < kClouds; ++k) {
    porter::point_cloud_t m{};
    m.utime = t0 + k * 100'000;
    m.frame_id = "lidar";
    m.scan_id = k;
    m.num_points = 1000;
    for (int i = 0; i < m.num_points; ++i) {
      const double a = 2.0 * M_PI * i / m.num_points;
      m.x_m.push_back(static_cast<float>(3.0 * std::cos(a)));
      m.y_m.push_back(static_cast<float>(3.0 * std::sin(a)));
      m.z_m.push_back(0.5f);
      m.time_offset_ns.push_back(i * 90'000);
    }
    m.intensity.assign(1000, 0.0f);
    m.line.assign(1000, 0);
    m.tag.assign(1000, 0);
    EXPECT_TRUE(bus.publish(porter::channels::kLidarPoints, m));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_EQ(::kill(mapper.pid(), SIGCONT), 0);
  int processed = 0, received = 0, busy = 0, dropped = 0, lost = 0;
  const auto counts = [&] {
    return std::sscanf(heartbeat.c_str(), "clouds %d/%d, arrived while busy %d, dropped %d, lost upstream %d", &processed,
                       &received, &busy, &dropped, &lost) == 5;
  };
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end && !(counts() && received == kClouds)) bus.handle_timeout(100);
  const int status = mapper.stop();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << mapper.log();
  ASSERT_TRUE(counts()) << heartbeat;
  EXPECT_EQ(received, kClouds) << heartbeat << "\n" << mapper.log();
  EXPECT_EQ(lost, 0) << heartbeat;
  std::printf("heartbeat: %s\n", heartbeat.c_str());
  std::remove(log_path.c_str());
}

}  // namespace
}  // namespace porter::mapping
