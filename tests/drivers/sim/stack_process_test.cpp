// The simulated robot end to end, every process started here and stopped by PID: porter-sim
// (Scout Mini and Piper firmware on the LCM-carried CAN buses, the simulated MID-360 sending UDP
// to loopback) with porter-base, porter-arm and porter-lidar, on a private udpm URL and free UDP
// ports, in the empty scene (nothing near the robot but the ground):
// - ARM_CMD moves the simulated arm once porter-arm has run the enable sequence (SIM_TRUTH and
//   ARM_STATE agree);
// - LIDAR_POINTS arrive at 10 Hz with 20,000 points per cloud, and points lie on the robot and
//   on the arm and payload turned to the left;
// - a box added with SIM_COMMAND ADD_BOX appears in the cloud where it was put;
// - BASE_CMD moves the simulated base (SIM_TRUTH, BASE_STATE);
// - the arm's power cycle (SIM_COMMAND POWER_CYCLE) is recovered by porter-arm: it re-enables the
//   arm and the next target is followed;
// - every process exits 0 on SIGTERM.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "instrumented_build.hpp"
#include "private_lcm_url.hpp"
#include "process_support.hpp"

namespace porter {
namespace {

using sim::test::Child;

/// The sensor's point frame in the base frame (shipped mount: 0.2875 m above lidar_mast at
/// (-0.22, 0, 0.245)); porter-lidar is told this extrinsic and publishes in the base frame.
constexpr double kSensorX = -0.22, kSensorZ = 0.245 + 0.2875;

std::string lidar_config(const std::string& url, int point_port, int imu_port) {
  std::string text = sim::test::shipped_config("porter_lidar.yaml");
  auto set = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  set("lcm_url: \"\"", "lcm_url: \"" + url + "\"");
  set("address: 0.0.0.0", "address: 127.0.0.1");
  set("point_port: 56301", "point_port: " + std::to_string(point_port));
  set("imu_port: 56401", "imu_port: " + std::to_string(imu_port));
  set("frame_id: lidar\n", "frame_id: base\n");
  set("extrinsic: {xyz: [0.0, 0.0, 0.0]",
      "extrinsic: {xyz: [" + std::to_string(kSensorX) + ", 0.0, " + std::to_string(kSensorZ) + "]");
  // Every ray as a point (no-return ones at the sensor's origin): the cloud size shows the rate.
  set("keep_no_return: false", "keep_no_return: true");
  return sim::test::write_temp("lidar.yaml", text);
}

std::string arm_config(const std::string& url) {
  std::string text = sim::test::shipped_config("porter_arm.yaml");
  const auto at = text.find("lcm_url: \"\"");
  EXPECT_NE(at, std::string::npos);
  text.replace(at, 11, "lcm_url: \"" + url + "\"");
  // porter-arm opens its bus spec as given (porter-base and porter-sim add their lcm_url to an
  // lcm: bus without one): the URL goes into the spec.
  const auto bus = text.find("can_bus: lcm:CAN_ARM");
  EXPECT_NE(bus, std::string::npos);
  text.replace(bus, 20, "can_bus: \"lcm:CAN_ARM@" + url + "\"");
  return sim::test::write_temp("arm.yaml", text);
}

/// A cloud in the base frame, reduced to what the test checks.
struct CloudSummary {
  std::int64_t utime = 0;
  int num_points = 0;
  int returns = 0;
  int self = 0;         ///< returns above the ground within 1.2 m of the base's centre
  int left_reach = 0;   ///< returns above the ground, 0.35..1.2 m left of the base (arm, payload)
  int in_box = 0;       ///< returns inside the test's box (base frame = world frame at start)
};

struct Observer : sim::test::BusObserver {
  explicit Observer(const std::string& url)
      // A 20,000-point cloud is a 440 kB burst of LCM fragments: the socket buffer must hold it.
      : BusObserver(url + "&recv_buf_size=4194304", "stack_process_test") {
    lcm.subscribe(channels::kSimTruth, [this](const porter::robot_state_t& s) {
      std::lock_guard<std::mutex> l(m);
      truth = s;
      ++truth_count;
    });
    lcm.subscribe(channels::kBaseState, [this](const porter::base_state_t& s) {
      std::lock_guard<std::mutex> l(m);
      base = s;
      ++base_count;
    });
    lcm.subscribe(channels::kArmState, [this](const porter::arm_state_t& s) {
      std::lock_guard<std::mutex> l(m);
      arm = s;
      ++arm_count;
    });
    lcm.subscribe(channels::kLidarPoints, [this](const porter::point_cloud_t& c) {
      const CloudSummary s = summarize(c);
      std::lock_guard<std::mutex> l(m);
      clouds.push_back(s);
    });
    listen();
  }
  ~Observer() { stop_listening(); }

  CloudSummary summarize(const porter::point_cloud_t& c) const {
    CloudSummary s;
    s.utime = c.utime;
    s.num_points = c.num_points;
    for (int i = 0; i < c.num_points; ++i) {
      const double x = c.x_m[i], y = c.y_m[i], z = c.z_m[i];
      if (std::abs(x - kSensorX) < 1e-4 && std::abs(y) < 1e-4 && std::abs(z - kSensorZ) < 1e-4) {
        continue;  // no return
      }
      ++s.returns;
      if (z > 0.03 && std::hypot(x, y) < 1.2) ++s.self;
      if (z > 0.03 && y > 0.35 && y < 1.2) ++s.left_reach;
      if (std::abs(x - box_x) < 0.26 && std::abs(y) < 1.01 && z > 0.03 && z < 1.01) ++s.in_box;
    }
    return s;
  }

  std::vector<CloudSummary> clouds_since(std::size_t from) {
    std::lock_guard<std::mutex> l(m);
    return std::vector<CloudSummary>(clouds.begin() + static_cast<long>(std::min(from, clouds.size())),
                                     clouds.end());
  }
  std::size_t cloud_count() {
    std::lock_guard<std::mutex> l(m);
    return clouds.size();
  }

  void arm_cmd(const std::vector<double>& q) {
    porter::arm_cmd_t c;
    c.utime = runtime::wall_utime();
    c.enabled = true;
    c.num_joints = 6;
    c.q_rad = q;
    c.qd_radps.assign(6, 0.0);
    c.speed_pct = 100;
    c.has_gripper = false;
    c.plan_id = -1;
    c.source = "stack_process_test";
    lcm.publish(channels::kArmCmd, c);
  }
  bool truth_q_near(const std::vector<double>& q, double tol) const {
    if (truth_count == 0 || truth.q_rad.size() != q.size()) return false;
    for (std::size_t j = 0; j < q.size(); ++j) {
      if (std::abs(truth.q_rad[j] - q[j]) > tol) return false;
    }
    return true;
  }

  const double box_x = -3.0;  // behind the robot: the arm and payload hide much of the view ahead
  porter::robot_state_t truth;
  porter::base_state_t base;
  porter::arm_state_t arm;
  std::vector<CloudSummary> clouds;
  long truth_count = 0, base_count = 0, arm_count = 0;
};

TEST(StackProcesses, SimulatedRobotWithBaseArmAndLidarDrivers) {
  const std::string url = test::private_lcm_url();
  const int point_port = test::free_udp_port();
  int imu_port = test::free_udp_port();
  if (imu_port == point_port) imu_port = test::free_udp_port();
  Observer obs(url);
  ASSERT_TRUE(obs.lcm.good());
  const std::string src = sim::test::kSource;
  Child lidar(PORTER_LIDAR_EXE, {"--config", lidar_config(url, point_port, imu_port)},
              "stack_porter_lidar.log");
  Child sim(PORTER_SIM_EXE,
            {"--config", sim::test::sim_config_file("stack_sim.yaml", point_port, imu_port),
             "--lcm-url", url, "--scene", src + "/config/scenes/empty.yaml"},
            "stack_porter_sim.log");
  Child base(PORTER_BASE_EXE,
             {"--config", src + "/config/drivers/porter_base.yaml", "--lcm-url", url},
             "stack_porter_base.log");
  Child arm(PORTER_ARM_EXE, {"--config", arm_config(url)}, "stack_porter_arm.log");
  ASSERT_GT(lidar.pid(), 0);
  ASSERT_GT(sim.pid(), 0);
  ASSERT_GT(base.pid(), 0);
  ASSERT_GT(arm.pid(), 0);
  auto logs = [&] {
    return "--- porter-sim\n" + sim.log() + "--- porter-arm\n" + arm.log() + "--- porter-base\n" +
           base.log() + "--- porter-lidar\n" + lidar.log();
  };

  // Both drivers take their devices over; the arm after its enable sequence.
  auto arm_ready = [&] {
    return obs.arm_count > 0 && obs.arm.link_ok && obs.arm.enabled &&
           obs.arm.ctrl_mode == porter::arm_state_t::CTRL_CAN;
  };
  ASSERT_TRUE(obs.wait_for(arm_ready, 30.0)) << logs();
  ASSERT_TRUE(obs.wait_for([&] {
    return obs.base_count > 0 && obs.base.link_ok &&
           obs.base.control_mode == porter::base_state_t::MODE_CAN;
  }, 20.0)) << logs();

  // ARM_CMD moves the simulated arm: turned left, so the payload is in the sensor's view.
  const std::vector<double> left = {0.8, 0.6, -0.9, 0.0, 0.5, 0.0};
  ASSERT_TRUE(obs.wait_for([&] { return obs.truth_q_near(left, 2e-3); }, 20.0,
                           [&] { obs.arm_cmd(left); }))
      << logs();
  EXPECT_TRUE(obs.wait_for([&] { return std::abs(obs.arm.q_rad[0] - 0.8) < 2e-3; }, 2.0,
                           [&] { obs.arm_cmd(left); }));

  // LIDAR_POINTS: 10 Hz, 20,000 points each, points on the robot and on the arm and payload.
  ASSERT_TRUE(obs.wait_for([&] { return obs.clouds.size() >= 3; }, 10.0)) << logs();
  std::size_t from = obs.cloud_count();
  std::this_thread::sleep_for(std::chrono::seconds(3));
  std::vector<CloudSummary> c = obs.clouds_since(from);
  // Under ASan the simulated MID-360 runs below real time (19 clouds in 3 s, its clock stepping):
  // the rate and the points per cloud are checked in a plain build, what the clouds hold in both.
  const bool real_time = !porter::test::kInstrumentedBuild;
  ASSERT_GE(c.size(), real_time ? 25u : 3u) << logs();
  if (real_time) {
    EXPECT_LE(c.size(), 35u);
    const double period_s = (c.back().utime - c.front().utime) * 1e-6 / (c.size() - 1);
    EXPECT_NEAR(period_s, 0.1, 0.005);
  }
  long points = 0, self = 0, left_reach = 0, in_box = 0;
  for (const CloudSummary& s : c) {
    points += s.num_points;
    self += s.self;
    left_reach += s.left_reach;
    in_box += s.in_box;
  }
  const double per_cloud = static_cast<double>(points) / c.size();
  if (real_time) {
    EXPECT_NEAR(per_cloud, 20000.0, 400.0);
  }
  EXPECT_GT(self / static_cast<double>(c.size()), 300.0) << "points on the robot per cloud";
  EXPECT_GT(left_reach / static_cast<double>(c.size()), 20.0) << "points on the arm and payload";
  EXPECT_EQ(in_box, 0);
  RecordProperty("points_per_cloud", std::to_string(per_cloud));
  RecordProperty("self_points_per_cloud", std::to_string(self / static_cast<double>(c.size())));
  RecordProperty("arm_payload_points_per_cloud", std::to_string(left_reach / static_cast<double>(c.size())));

  // SIM_COMMAND ADD_BOX: the box shows up in the cloud, where it was put.
  obs.sim_command(porter::sim_command_t::ADD_BOX, "crate", 0,
                  {obs.box_x, 0.0, 0.5, 0.5, 2.0, 1.0});
  from = obs.cloud_count();
  EXPECT_TRUE(obs.wait_for([&] {
    for (std::size_t i = from; i < obs.clouds.size(); ++i) {
      if (obs.clouds[i].in_box > 200) return true;
    }
    return false;
  }, 5.0)) << logs();

  // BASE_CMD moves the simulated base.
  double x0 = 0, y0 = 0;
  {
    std::lock_guard<std::mutex> l(obs.m);
    x0 = obs.truth.x_m;
    y0 = obs.truth.y_m;
  }
  const double drive_end = runtime::mono_s() + 2.0;
  obs.wait_for([&] { return runtime::mono_s() > drive_end; }, 3.0, [&] { obs.base_cmd(0.3, 0.0); });
  {
    std::lock_guard<std::mutex> l(obs.m);
    EXPECT_NEAR(obs.truth.v_mps, 0.3, 0.005);
    EXPECT_NEAR(obs.base.v_mps, 0.3, 0.005);
    EXPECT_GT(std::hypot(obs.truth.x_m - x0, obs.truth.y_m - y0), 0.3);
  }

  // The arm's power cycle: the link drops, porter-arm re-enables the arm, targets move it again.
  obs.sim_command(porter::sim_command_t::POWER_CYCLE, "piper", 0.5);
  EXPECT_TRUE(obs.wait_for([&] { return !obs.arm.link_ok; }, 5.0)) << logs();
  const std::vector<double> right = {-0.5, 0.7, -1.0, 0.1, 0.4, 0.0};
  EXPECT_TRUE(obs.wait_for([&] { return arm_ready() && obs.truth_q_near(right, 2e-3); }, 20.0,
                           [&] { obs.arm_cmd(right); }))
      << logs();

  EXPECT_EQ(arm.stop(), 0) << arm.log();
  EXPECT_EQ(base.stop(), 0) << base.log();
  EXPECT_EQ(lidar.stop(), 0) << lidar.log();
  const std::string sim_log = sim.log();
  EXPECT_EQ(sim.stop(), 0) << sim_log;
  const std::string arm_log = arm.log();
  // The enable sequence ran twice: at start and after the power cycle.
  int enables = 0;
  for (auto at = arm_log.find("-> enabling"); at != std::string::npos; at = arm_log.find("-> enabling", at + 1)) {
    ++enables;
  }
  EXPECT_GE(enables, 2) << arm_log;
  EXPECT_NE(sim_log.find("power-cycled 'piper'"), std::string::npos) << sim_log;
  EXPECT_NE(sim_log.find("added box 'crate'"), std::string::npos) << sim_log;
}

}  // namespace
}  // namespace porter
