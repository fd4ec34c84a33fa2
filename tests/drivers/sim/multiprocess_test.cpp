// porter-base and porter-sim as separate processes over lcm:CAN_BASE on a private udpm port,
// started from the shipped configs (porter-sim's LiDAR off) and stopped by PID: the base enters
// command mode, BASE_CMD moves the simulated robot (SIM_TRUTH, LIO_POSE, BASE_STATE agree),
// SIM_COMMAND faults reach the firmware (power cycle and re-enable, an obstacle added and removed
// is acknowledged in the log), porter-base survives porter-sim restarting, both exit 0 on SIGTERM.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "private_lcm_url.hpp"
#include "process_support.hpp"

namespace porter {
namespace {

using sim::test::Child;
using sim::test::kSource;

// A free port: udpm traffic is host-wide, other runs of this test must not cross.
const std::string kUrl = test::private_lcm_url();

std::unique_ptr<Child> start_sim(int run) {
  return std::make_unique<Child>(
      PORTER_SIM_EXE,
      std::vector<std::string>{"--config", sim::test::sim_config_file("sim.yaml", 0, 0),
                               "--lcm-url", kUrl},
      "multiprocess_porter_sim_" + std::to_string(run) + ".log");
}

struct Observer : sim::test::BusObserver {
  explicit Observer(const std::string& url) : BusObserver(url, "multiprocess_test") {
    lcm.subscribe(channels::kBaseState, [this](const porter::base_state_t& s) {
      std::lock_guard<std::mutex> l(m);
      base = s;
      ++base_count;
    });
    lcm.subscribe(channels::kSimTruth, [this](const porter::robot_state_t& s) {
      std::lock_guard<std::mutex> l(m);
      truth = s;
      ++truth_count;
    });
    lcm.subscribe(channels::kLioPose, [this](const porter::pose_t& p) {
      std::lock_guard<std::mutex> l(m);
      lio = p;
      ++lio_count;
    });
    listen();
  }
  ~Observer() { stop_listening(); }
  void stream(double v, double w, double seconds) {
    const double end = runtime::mono_s() + seconds;
    while (runtime::mono_s() < end) {
      base_cmd(v, w);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  porter::base_state_t base;
  porter::robot_state_t truth;
  porter::pose_t lio;
  long base_count = 0, truth_count = 0, lio_count = 0;
};

bool contains(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

TEST(MultiProcess, PorterBaseDrivesPorterSimOverLcmCan) {
  Observer obs(kUrl);
  auto sim = start_sim(1);
  Child base(PORTER_BASE_EXE,
             {"--config", kSource + "/config/drivers/porter_base.yaml", "--lcm-url", kUrl},
             "multiprocess_porter_base.log");
  ASSERT_GT(sim->pid(), 0);
  ASSERT_GT(base.pid(), 0);
  auto in_can_mode = [&] {
    return obs.base_count > 0 && obs.base.link_ok &&
           obs.base.control_mode == porter::base_state_t::MODE_CAN;
  };
  ASSERT_TRUE(obs.wait_for(in_can_mode, 20.0)) << base.log() << sim->log();
  double x0 = 0, y0 = 0;
  ASSERT_TRUE(obs.wait_for([&] { return obs.truth_count > 0 && obs.lio_count > 0; }, 5.0));
  {
    std::lock_guard<std::mutex> l(obs.m);
    x0 = obs.truth.x_m;
    y0 = obs.truth.y_m;
    EXPECT_EQ(obs.truth.pose_source, porter::robot_state_t::POSE_SIM_TRUTH);
    EXPECT_EQ(obs.truth.num_joints, 6);
  }
  obs.stream(0.3, 0.0, 2.0);
  {
    std::lock_guard<std::mutex> l(obs.m);
    EXPECT_NEAR(obs.base.v_mps, 0.3, 0.002);
    EXPECT_NEAR(obs.truth.v_mps, 0.3, 0.002);
    const double moved = std::hypot(obs.truth.x_m - x0, obs.truth.y_m - y0);
    EXPECT_GT(moved, 0.3);
    // Wheel odometry (porter-base) and LIO (porter-sim) see the same motion.
    EXPECT_NEAR(std::hypot(obs.base.odom_x_m, obs.base.odom_y_m), moved, 0.1);
    EXPECT_NEAR(obs.lio.x_m, obs.truth.x_m, 0.1);
  }
  // Power cycle over SIM_COMMAND: the link drops, the driver re-enables the base.
  obs.sim_command(porter::sim_command_t::POWER_CYCLE, "scout_mini", 0.6);
  EXPECT_TRUE(obs.wait_for([&] { return !obs.base.link_ok; }, 5.0));
  EXPECT_TRUE(obs.wait_for(in_can_mode, 10.0));
  obs.stream(0.2, 0.0, 1.5);
  EXPECT_TRUE(obs.wait_for([&] { return std::abs(obs.base.v_mps - 0.2) < 0.002; }, 1.0));
  // World changes and refusals are acknowledged in porter-sim's log.
  obs.sim_command(porter::sim_command_t::ADD_BOX, "crate", 0, {3.0, 0.0, 0.5});
  obs.sim_command(porter::sim_command_t::REMOVE_OBSTACLE, "crate");
  obs.sim_command(porter::sim_command_t::POWER_CYCLE, "no_such_device", 0.1);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::string sim_log = sim->log();
  EXPECT_TRUE(contains(sim_log, "added box 'crate'")) << sim_log;
  EXPECT_TRUE(contains(sim_log, "removed obstacle 'crate'")) << sim_log;
  EXPECT_TRUE(contains(sim_log, "refused: no device 'no_such_device'")) << sim_log;

  // porter-sim restarts: porter-base loses the link and picks the new base up again.
  EXPECT_EQ(sim->stop(), 0) << sim->log();
  EXPECT_TRUE(obs.wait_for([&] { return !obs.base.link_ok; }, 5.0));
  sim = start_sim(2);
  EXPECT_TRUE(obs.wait_for(in_can_mode, 20.0)) << base.log();
  obs.stream(0.2, 0.0, 1.0);
  EXPECT_TRUE(obs.wait_for([&] { return std::abs(obs.base.v_mps - 0.2) < 0.002; }, 1.0));

  const int base_exit = base.stop();
  const std::string base_log = base.log();
  EXPECT_EQ(base_exit, 0) << base_log;
  EXPECT_EQ(sim->stop(), 0) << sim->log();
  EXPECT_TRUE(contains(base_log, "CAN feedback lost")) << base_log;
  EXPECT_TRUE(contains(base_log, "stopping: sent a zero 0x111")) << base_log;
}

}  // namespace
}  // namespace porter
