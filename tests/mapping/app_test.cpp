// porter-mapper's process logic without the process: strict config, the cloud queue and its
// counters, waiting for ROBOT_STATE, and a replay of an LCM log file giving the same map.
#include <unistd.h>

#include <cstdio>
#include <map>
#include <random>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "mapper_conversions.hpp"
#include "mapper_node.hpp"
#include "mapping_support.hpp"
#include "porter/core/load_error.hpp"
#include "porter/lcm_bus.hpp"
#include "hostile_config.hpp"

namespace porter::mapping {
namespace {

using livox::sim::Waypoint;

std::string shipped_text() {
  std::ifstream in(test::config_path("mapping/porter_mapper.yaml"));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes `text` next to the shipped config (relative paths resolve the same) and loads it.
app::MapperConfig load_text(const std::string& text) {
  const std::string path = test::config_path("mapping/.test_porter_mapper_" + std::to_string(::getpid()) + ".yaml");
  { std::ofstream(path) << text; }
  struct Remove {
    std::string p;
    ~Remove() { std::remove(p.c_str()); }
  } remove{path};
  return app::load_mapper_config(path);
}

void expect_load_error(const std::string& text, const std::string& key) {
  try {
    load_text(text);
    ADD_FAILURE() << "loaded; expected an error naming " << key;
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("porter_mapper"), std::string::npos) << e.what();
  }
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(MapperConfig, ShippedConfigLoadsAndIsStrict) {
  const app::MapperConfig cfg = test::shipped_config();
  EXPECT_DOUBLE_EQ(cfg.mapper.map.resolution_m, 0.05);
  EXPECT_EQ(cfg.mapper.map.dims, Eigen::Vector3i(400, 400, 64));
  EXPECT_NEAR(cfg.mapper.T_B_S.translation().z(), 0.5325, 1e-12);
  EXPECT_FALSE(cfg.payload_yaml.empty());
  const std::string text = shipped_text();
  expect_load_error(text + "\nsurprise: 1\n", "surprise");
  expect_load_error(replace(text, "  margin_m: 0.05\n", ""), "margin_m");
  expect_load_error(replace(text, "  margin_m: 0.05", "  margin_m: -0.05"), "margin_m");
  expect_load_error(replace(text, "  max_clouds: 12", "  max_clouds: 0"), "max_clouds");
  expect_load_error(replace(text, "  size_voxels: [400, 400, 64]", "  size_voxels: [400.5, 400, 64]"), "size_voxels");
  expect_load_error(replace(text, "  prob_hit: 0.7", "  prob_hit: 0.3"), "prob_hit");
  expect_load_error(replace(text, "publish_rate_hz: 2.0", "publish_rate_hz: abc"), "publish_rate_hz");
}

porter::robot_state_t state_msg(std::int64_t utime, const RobotConfiguration& c) {
  porter::robot_state_t m{};
  m.utime = utime;
  m.frame_id = "world";
  m.x_m = c.base.x_m;
  m.y_m = c.base.y_m;
  m.yaw_rad = c.base.yaw_rad;
  m.num_joints = kNumArmJoints;
  m.q_rad.assign(c.q_rad.data(), c.q_rad.data() + kNumArmJoints);
  m.qd_radps.assign(kNumArmJoints, 0.0);
  m.pose_source = porter::robot_state_t::POSE_SIM_TRUTH;
  m.pose_valid = m.arm_valid = m.base_valid = true;
  return m;
}

porter::point_cloud_t cloud_msg(const SensorCloud& c, std::int64_t scan_id) {
  porter::point_cloud_t m{};
  m.utime = c.utime;
  m.frame_id = "lidar";
  m.scan_id = scan_id;
  m.num_points = static_cast<std::int32_t>(c.size());
  m.x_m = c.x_m;
  m.y_m = c.y_m;
  m.z_m = c.z_m;
  m.intensity.assign(c.size(), 100.0f);
  m.time_offset_ns = c.time_offset_ns;
  m.line.assign(c.size(), 0);
  m.tag.assign(c.size(), 0);
  return m;
}

app::MapperConfig small_config() {
  app::MapperConfig cfg = test::shipped_config();
  cfg.mapper.map.dims = {200, 200, 48};
  cfg.mapper.max_range_m = 4.5;
  return cfg;
}

TEST(MapperNode, CountsCloudsArrivingWhileBusyAndWaitsForTheState) {
  app::MapperConfig cfg = small_config();
  cfg.max_queued_clouds = 1;
  const RobotModel robot = test::robot_with("long_bar");
  app::MapperNode node(cfg, robot);
  SensorCloud c;
  c.utime = 2'000'000;
  for (int i = 0; i < 100; ++i) {
    c.x_m.push_back(2.0f);
    c.y_m.push_back(0.01f * i);
    c.z_m.push_back(0.0f);
    c.time_offset_ns.push_back(i * 1'000'000);  // last point at +99 ms
  }
  node.on_state(state_msg(1'950'000, test::config_at(0, 0, 0)));
  node.on_cloud(cloud_msg(c, 1), 0);
  app::StepResult r;
  EXPECT_FALSE(node.step(1'000'000, 0, r));  // no state at the scan's end yet, 1 ms waited
  node.on_cloud(cloud_msg(c, 2), 2'000'000);  // arrives while the first waits; the queue holds one
  node.on_cloud(cloud_msg(c, 5), 3'000'000);  // 3 and 4 never arrived
  app::MapperCounters k = node.counters();
  EXPECT_EQ(k.clouds_received, 3u);
  EXPECT_EQ(k.arrived_while_busy, 2u);
  // The clouds the full queue pushed out were still waiting for their state.
  EXPECT_EQ(k.dropped_queue_full, 0u);
  EXPECT_EQ(k.dropped_no_state, 2u);
  EXPECT_EQ(k.lost_upstream, 2u);
  node.on_state(state_msg(2'100'000, test::config_at(0, 0, 0)));
  // Covered, waiting for the worker: pushed out by the next cloud, a queue drop.
  node.on_cloud(cloud_msg(c, 6), 3'000'000);
  k = node.counters();
  EXPECT_EQ(k.dropped_queue_full, 1u);
  EXPECT_EQ(k.dropped_no_state, 2u);
  ASSERT_TRUE(node.step(3'000'001, 0, r));
  EXPECT_EQ(r.scan_id, 6);
  EXPECT_TRUE(r.map_due);
  EXPECT_EQ(r.report.filter.state_outside, 0u);
  EXPECT_EQ(r.report.integrate.hits, 100u);
  EXPECT_FALSE(node.step(3'000'002, 0, r));

  // A cloud whose arm sample never comes is dropped (and counted), not filtered with a held
  // state, once the states pass its last point (5.099 s) by state.wait_s: on the states' time,
  // however long the cloud has waited on the wall clock.
  c.utime = 5'000'000;
  node.on_cloud(cloud_msg(c, 7), 10'000'000);
  EXPECT_FALSE(node.step(10'000'000 + static_cast<std::int64_t>(10 * cfg.state_wait_s * 1e9), 0, r));
  EXPECT_EQ(node.counters().dropped_no_state, 2u);
  const auto base_only = [](std::int64_t utime) {
    porter::robot_state_t m = state_msg(utime, test::config_at(0, 0, 0));
    m.num_joints = 0;
    m.q_rad.clear();
    m.qd_radps.clear();
    return m;
  };
  const std::int64_t deadline_us = 5'099'000 + static_cast<std::int64_t>(cfg.state_wait_s * 1e6);
  node.on_state(base_only(5'200'000));
  node.on_state(base_only(deadline_us));
  EXPECT_FALSE(node.step(20'000'000'000, 0, r));
  EXPECT_EQ(node.counters().dropped_no_state, 2u);
  node.on_state(base_only(deadline_us + 1));
  EXPECT_FALSE(node.step(20'000'000'001, 0, r));
  EXPECT_EQ(node.counters().dropped_no_state, 3u);
  EXPECT_EQ(node.counters().clouds_processed, 1u);

  // Malformed input is counted, not processed.
  porter::point_cloud_t bad = cloud_msg(c, 8);
  bad.frame_id = "base";
  node.on_cloud(bad, 11'000'000'000);
  bad = cloud_msg(c, 9);
  bad.time_offset_ns[3] = -5;
  node.on_cloud(bad, 11'000'000'001);
  porter::robot_state_t bad_state = state_msg(6'000'000, test::config_at(0, 0, 0));
  bad_state.num_joints = 3;
  bad_state.q_rad.resize(3);
  node.on_state(bad_state);
  k = node.counters();
  EXPECT_EQ(k.rejected, 3u);
  EXPECT_NE(k.last_reject.find("num_joints"), std::string::npos) << k.last_reject;
  EXPECT_FALSE(node.step(12'000'000'000, 0, r));
}

TEST(MapperNode, PosesTheArmOnArmUtimeAndNeedsBothBaseAndArmToCoverACloud) {
  app::MapperConfig cfg = small_config();
  cfg.max_queued_clouds = 4;
  const RobotModel robot = test::robot_with("long_bar");
  app::MapperNode node(cfg, robot);
  SensorCloud c;
  c.utime = 2'000'000;
  for (int i = 0; i < 100; ++i) {
    c.x_m.push_back(2.0f);
    c.y_m.push_back(0.01f * i);
    c.z_m.push_back(0.0f);
    c.time_offset_ns.push_back(i * 1'000'000);  // first point at 2.0 s, last at 2.099 s
  }
  // States without joints (porter-state before the first ARM_STATE) pose the base only.
  for (std::int64_t t = 1'900'000; t <= 2'200'000; t += 10'000) {
    porter::robot_state_t m = state_msg(t, test::config_at(0, 0, 0));
    m.num_joints = 0;
    m.q_rad.clear();
    m.qd_radps.clear();
    node.on_state(m);
  }
  EXPECT_EQ(node.counters().states_without_arm, 31u);
  node.on_cloud(cloud_msg(c, 1), 0);
  app::StepResult r;
  EXPECT_FALSE(node.step(1'000'000, 0, r));  // the arm is unknown: no cloud is filtered with q = 0
  // Joint angles stamped with their own time (arm_utime), 0.2 s before utime: the arm track
  // holds 2.01..2.13 s. Scan 1 begins before it and can never be covered: dropped at once.
  for (std::int64_t t = 2'210'000; t <= 2'330'000; t += 10'000) {
    porter::robot_state_t m = state_msg(t, test::config_at(0, 0, 0));
    m.arm_utime = t - 200'000;
    node.on_state(m);
  }
  EXPECT_FALSE(node.step(2'000'000, 0, r));
  EXPECT_EQ(node.counters().dropped_no_state, 1u);
  // Scan 2 (2.02..2.119 s) lies inside both tracks.
  c.utime = 2'020'000;
  node.on_cloud(cloud_msg(c, 2), 3'000'000);
  ASSERT_TRUE(node.step(3'000'000, 0, r));
  EXPECT_EQ(r.scan_id, 2);
  EXPECT_EQ(r.report.filter.state_outside, 0u);
  // Scan 3 ends at 2.149 s, after the newest arm sample (2.13 s), though the base reaches 2.33 s.
  c.utime = 2'050'000;
  node.on_cloud(cloud_msg(c, 3), 4'000'000);
  EXPECT_FALSE(node.step(4'000'000, 0, r));
  porter::robot_state_t m = state_msg(2'400'000, test::config_at(0, 0, 0));
  m.arm_utime = 2'000'000;  // not newer than the arm track's newest: ignored
  node.on_state(m);
  EXPECT_FALSE(node.step(4'000'001, 0, r));
  m = state_msg(2'410'000, test::config_at(0, 0, 0));
  m.arm_utime = 2'150'000;
  node.on_state(m);
  ASSERT_TRUE(node.step(4'000'002, 0, r));
  EXPECT_EQ(r.scan_id, 3);
  EXPECT_EQ(r.report.filter.state_outside, 0u);
  const app::MapperCounters k = node.counters();
  EXPECT_EQ(k.clouds_processed, 2u);
  EXPECT_EQ(k.dropped_no_state, 1u);
  EXPECT_EQ(k.states_without_arm, 31u);
}

// One delivery of a drive's messages to a node: what it integrated and the map stream after
// every integrated cloud (keyed by the map's utime, the cloud's last point).
struct Delivery {
  std::map<std::int64_t, std::vector<std::uint8_t>> maps;
  app::MapperCounters counters;
};

// The same clouds and states reach porter-mapper's node in different interleavings and with
// different delays, as a replay of one log on a busy machine gives them: the node must
// integrate the same clouds, from the same states, into the same maps.
TEST(MapperNode, TheSameMessagesInAnyInterleavingAndTimingGiveTheSameMaps) {
  const Scene scene = load_scene(test::config_path("scenes/forest.yaml"));
  app::MapperConfig cfg = small_config();
  cfg.max_queued_clouds = 64;  // no queue drop: every cloud reaches the state rule
  cfg.state_wait_s = 0.5;      // shorter than the arm samples' gap below
  const RobotModel robot = test::robot_with("long_bar");
  const double y = test::clear_lane(scene, 2.5, 0.4);
  test::SimDrive drive(robot, scene.obstacles,
                       {Waypoint{0.0, test::config_at(0.0, y, 0.0)}, Waypoint{2.0, test::config_at(1.6, y, 0.3)}},
                       cfg.mapper.T_B_S);
  constexpr int kClouds = 20;
  std::vector<porter::point_cloud_t> clouds;
  std::vector<std::pair<std::int64_t, RobotConfiguration>> samples;
  StateBuffer unused;
  for (int k = 0; k < kClouds; ++k) clouds.push_back(cloud_msg(drive.next(unused, &samples).cloud, k));
  // ROBOT_STATE at 100 Hz; from 0.8 s to 1.5 s porter-state has no new arm sample and repeats
  // the one of 0.8 s: the clouds that end in the first 0.2 s of that gap are not covered before
  // the states pass them by state.wait_s (0.5 s) and must be dropped, whatever the timing.
  const std::int64_t freeze0 = test::SimDrive::kEpochUs + 800'000, freeze1 = test::SimDrive::kEpochUs + 1'500'000;
  std::vector<porter::robot_state_t> states;
  RobotConfiguration held;
  for (const auto& [t, c] : samples) {
    porter::robot_state_t m = state_msg(t, c);
    if (t <= freeze0) held = c;
    if (t > freeze0 && t < freeze1) {
      m.arm_utime = freeze0;
      m.q_rad.assign(held.q_rad.data(), held.q_rad.data() + kNumArmJoints);
    } else {
      m.arm_utime = t;
    }
    states.push_back(m);
  }
  // A message with the (wall-clock) time it is delivered at, in ns.
  struct Event {
    std::int64_t at_ns;
    int cloud;  // index into clouds, or -1 - index into states
  };
  const auto deliver = [&](std::vector<Event> events, bool step_each) {
    std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.at_ns < b.at_ns; });
    app::MapperNode node(cfg, robot);
    Delivery d;
    porter::octomap_t map;
    app::StepResult r;
    const auto drain = [&](std::int64_t now_ns) {
      while (node.step(now_ns, 0, r)) {
        node.make_map(map);
        d.maps[map.utime] = map.data;
      }
    };
    for (const Event& e : events) {
      if (e.cloud >= 0) {
        node.on_cloud(clouds[static_cast<std::size_t>(e.cloud)], e.at_ns);
      } else {
        node.on_state(states[static_cast<std::size_t>(-1 - e.cloud)]);
      }
      if (step_each) drain(e.at_ns);
    }
    drain(events.back().at_ns + 60'000'000'000);
    d.counters = node.counters();
    return d;
  };
  const auto utime_ns = [](std::int64_t utime_us) { return (utime_us - test::SimDrive::kEpochUs) * 1000; };
  const auto end_us = [&](int k) {
    const porter::point_cloud_t& c = clouds[static_cast<std::size_t>(k)];
    return c.utime + *std::max_element(c.time_offset_ns.begin(), c.time_offset_ns.end()) / 1000;
  };

  // Live order: each cloud 5 ms after its last point, each state 2 ms after its time.
  std::vector<Event> live;
  for (int k = 0; k < kClouds; ++k) live.push_back({utime_ns(end_us(k)) + 5'000'000, k});
  for (std::size_t i = 0; i < states.size(); ++i) {
    live.push_back({utime_ns(states[i].utime) + 2'000'000, -1 - static_cast<int>(i)});
  }
  const Delivery reference = deliver(live, true);
  // Integrated: the clouds that begin at or after the first state and do not end in the first
  // state.wait_s (0.5 s) before the arm track resumes at 1.5 s.
  std::uint64_t expected = 0, in_gap = 0;
  for (int k = 0; k < kClouds; ++k) {
    const porter::point_cloud_t& c = clouds[static_cast<std::size_t>(k)];
    const std::int64_t start = c.utime + *std::min_element(c.time_offset_ns.begin(), c.time_offset_ns.end()) / 1000;
    const bool gap = end_us(k) >= freeze0 && end_us(k) < freeze1 - 500'000;
    const bool integrated = start >= states.front().utime && !gap;
    in_gap += gap;
    expected += integrated;
    EXPECT_EQ(reference.maps.count(end_us(k)), integrated ? 1u : 0u) << "cloud " << k;
  }
  EXPECT_EQ(in_gap, 2u);  // the clouds ending in 0.8..1.0 s
  EXPECT_EQ(reference.counters.clouds_processed, expected);
  EXPECT_EQ(reference.counters.dropped_no_state, kClouds - expected);
  EXPECT_EQ(reference.maps.size(), expected);

  std::vector<std::pair<std::string, std::vector<Event>>> variants;
  // The states 2 s late (longer than state.wait_s on the wall clock), every cloud waiting.
  std::vector<Event> late = live;
  for (Event& e : late) e.at_ns += e.cloud < 0 ? 2'000'000'000 : 0;
  variants.emplace_back("states 2 s late", late);
  // The states stalled for 1.2 s from 0.5 s on, then delivered at once.
  std::vector<Event> stall = live;
  for (Event& e : stall) {
    if (e.cloud < 0 && e.at_ns >= 500'000'000 && e.at_ns < 1'700'000'000) e.at_ns = 1'700'000'000;
  }
  variants.emplace_back("states stalled 1.2 s", stall);
  // Every cloud after all states (a cloud arriving after the states that pass its deadline).
  std::vector<Event> clouds_last = live;
  for (Event& e : clouds_last) e.at_ns += e.cloud >= 0 ? 10'000'000'000 : 0;
  variants.emplace_back("clouds after every state", clouds_last);
  // Random delays of up to 1.5 s per message, seeded.
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int64_t> delay(0, 1'500'000'000);
  for (int v = 0; v < 3; ++v) {
    std::vector<Event> shuffled = live;
    for (Event& e : shuffled) e.at_ns += delay(rng);
    // Messages of one kind keep their order (one sender, one socket).
    std::vector<std::int64_t> c_at, s_at;
    for (const Event& e : shuffled) (e.cloud >= 0 ? c_at : s_at).push_back(e.at_ns);
    std::sort(c_at.begin(), c_at.end());
    std::sort(s_at.begin(), s_at.end());
    std::size_t ci = 0, si = 0;
    for (Event& e : shuffled) e.at_ns = e.cloud >= 0 ? c_at[ci++] : s_at[si++];
    variants.emplace_back("random delays " + std::to_string(v), shuffled);
  }
  for (const auto& [name, events] : variants) {
    for (const bool step_each : {true, false}) {  // the worker right away, or after everything
      const Delivery d = deliver(events, step_each);
      const std::string what = name + (step_each ? ", worker right away" : ", worker late");
      EXPECT_EQ(d.counters.clouds_processed, reference.counters.clouds_processed) << what;
      EXPECT_EQ(d.counters.dropped_no_state, reference.counters.dropped_no_state) << what;
      EXPECT_EQ(d.counters.dropped_queue_full, 0u) << what;
      EXPECT_EQ(d.maps.size(), reference.maps.size()) << what;
      for (const auto& [utime, bytes] : reference.maps) {
        const auto it = d.maps.find(utime);
        ASSERT_NE(it, d.maps.end()) << what << ": no map of the scan ending at " << utime;
        EXPECT_TRUE(it->second == bytes) << what << ": the map of the scan ending at " << utime << " differs";
      }
    }
  }
}

/// Runs every event of an LCM log through a fresh node on an in-process bus; the final map.
porter::octomap_t replay(const std::string& log_path, const app::MapperConfig& cfg, const RobotModel& robot) {
  porter::LcmBus bus("memq://");
  app::MapperNode node(cfg, robot);
  bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& m) { node.on_state(m); }, 1000);
  bus.subscribe(porter::channels::kLidarPoints, [&](const porter::point_cloud_t& m) { node.on_cloud(m, 0); }, 100);
  lcm::LogFile log(log_path, "r");
  EXPECT_TRUE(log.good());
  app::StepResult r;
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent()) {
    bus.lcm().publish(ev->channel, ev->data, static_cast<unsigned>(ev->datalen));
    bus.handle_pending();
    while (node.step(0, 0, r)) {
    }
  }
  porter::octomap_t map;
  node.make_map(map);
  return map;
}

TEST(MapperReplay, ARecordedLogReplayedThroughTheMapperGivesTheSameMap) {
  const Scene scene = load_scene(test::config_path("scenes/forest.yaml"));
  const app::MapperConfig cfg = small_config();
  const RobotModel robot = test::robot_with("long_bar");
  const double y = test::clear_lane(scene, 2.5, 0.4);
  test::SimDrive drive(robot, scene.obstacles,
                       {Waypoint{0.0, test::config_at(0.0, y, 0.0)}, Waypoint{1.2, test::config_at(1.0, y, 0.2)}},
                       cfg.mapper.T_B_S);
  const std::string log_path = ::testing::TempDir() + "porter_mapper_replay_" + std::to_string(::getpid()) + ".lcmlog";

  // Live: messages go to the mapper over the bus as they are made, and into the log.
  porter::octomap_t live;
  {
    lcm::LogFile log(log_path, "w");
    ASSERT_TRUE(log.good());
    porter::LcmBus bus("memq://");
    app::MapperNode node(cfg, robot);
    bus.subscribe(porter::channels::kRobotState, [&](const porter::robot_state_t& m) { node.on_state(m); }, 1000);
    bus.subscribe(porter::channels::kLidarPoints, [&](const porter::point_cloud_t& m) { node.on_cloud(m, 0); }, 100);
    std::int64_t event_time = test::SimDrive::kEpochUs;
    auto send = [&](const std::string& channel, const auto& msg) {
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
      msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
      lcm::LogEvent ev{0, event_time++, channel, static_cast<std::int32_t>(buf.size()), buf.data()};
      log.writeEvent(&ev);
      bus.lcm().publish(channel, buf.data(), static_cast<unsigned>(buf.size()));
      bus.handle_pending();
    };
    StateBuffer unused;
    std::vector<std::pair<std::int64_t, RobotConfiguration>> states;
    std::size_t sent = 0;
    app::StepResult r;
    for (int k = 0; k < 12; ++k) {
      const test::SimCloud c = drive.next(unused, &states);
      for (; sent < states.size(); ++sent) {
        send(std::string(porter::channels::kRobotState.name()), state_msg(states[sent].first, states[sent].second));
      }
      send(std::string(porter::channels::kLidarPoints.name()), cloud_msg(c.cloud, k));
      while (node.step(0, 0, r)) EXPECT_EQ(r.report.filter.state_outside, 0u);
    }
    const app::MapperCounters kc = node.counters();
    EXPECT_EQ(kc.clouds_processed, 12u) << kc.clouds_received << " received, " << kc.dropped_queue_full << " dropped, " << kc.states_received << " states, rejected " << kc.rejected << " " << kc.last_reject << "; bus decode failures " << bus.decode_failures();
    node.make_map(live);
  }
  const porter::octomap_t again = replay(log_path, cfg, robot);
  std::remove(log_path.c_str());

  ASSERT_GT(live.num_bytes, 1000);
  EXPECT_EQ(again.num_bytes, live.num_bytes);
  EXPECT_TRUE(again.data == live.data);
  EXPECT_EQ(again.utime, live.utime);
  EXPECT_DOUBLE_EQ(again.robot_x_m, live.robot_x_m);
  EXPECT_NEAR(live.robot_x_m, 1.0, 1e-3);  // the pose at the last point, just before 1.2 s
  EXPECT_NEAR(live.robot_y_m, y, 1e-9);
  // The stream reads back with obstacles in it.
  octomap::OcTree tree(live.resolution_m);
  std::istringstream in(std::string(live.data.begin(), live.data.end()));
  tree.readBinaryData(in);
  std::int64_t occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) occupied += tree.isNodeOccupied(*it);
  EXPECT_GT(occupied, 500);
}

}  // namespace
}  // namespace porter::mapping

// Every number of the shipped file replaced by hostile values: NaN, infinities and 1e300 are
// refused naming the file; 0, -1, 1e-300, 1e9 load or are refused, never crash
// (tests/support/hostile_config.hpp).
TEST(MapperConfigHostile, EveryNumberIsRangeChecked) {
  const int replaced = porter::test::check_hostile_numbers("mapping/porter_mapper.yaml", [](const std::string& f) { porter::mapping::app::load_mapper_config(f); });
  EXPECT_GE(replaced, 11 * 32);
}
