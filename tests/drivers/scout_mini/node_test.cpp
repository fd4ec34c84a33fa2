// porter-base's real loop against the simulated Scout Mini, in real time, over the in-memory bus
// and over the LCM-carried bus (lcm:CAN_BASE on a private udpm port): enable sequence, command
// streaming, stale-command stop, e-stop, re-enable after a power cycle, fault decoding, clean
// shutdown. BASE_CMD / ESTOP / BASE_STATE travel over LCM as in the running stack.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <vector>

#include "private_lcm_url.hpp"
#include "node_harness.hpp"

namespace porter::scout_mini {
namespace {

using test::Client;
using test::DriverProcess;
using test::SimulatedBase;

struct Transport {
  const char* name;
  bool lcm_can;
};
void PrintTo(const Transport& t, std::ostream* os) { *os << t.name; }

// Each test gets its own free udpm port so parallel runs never cross.
class BaseNodeTest : public ::testing::TestWithParam<Transport> {
 protected:
  std::string lcm_url() const { return porter::test::private_lcm_url(); }
  std::string can_spec(const std::string& lcm, const std::string& name) const {
    return GetParam().lcm_can ? "lcm:CAN_BASE@" + lcm : "memory:" + name;
  }
};

bool in_can_mode(const porter::base_state_t& s) {
  return s.link_ok && s.control_mode == porter::base_state_t::MODE_CAN;
}

TEST_P(BaseNodeTest, EnablesStreamsAndStopsWhenCommandsGoStale) {
  const std::string lcm = lcm_url();
  const std::string can = can_spec(lcm, "node_stream");
  SimulatedBase base(can);
  ASSERT_TRUE(base.open()) << base.error();
  std::mutex m;
  std::vector<MotionCommand> sent;
  base.tap([&](const std::string&, const can::CanFrame& f, bool from_device) {
    MotionCommand c;
    if (!from_device && decode_motion_command(f, c) == DecodeStatus::ok) {
      std::lock_guard<std::mutex> lock(m);
      sent.push_back(c);
    }
  });
  Client client(lcm);
  DriverProcess driver(test::node_config(can), lcm);
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0)) << "the base never reached CAN command mode";
  client.stream(0.3, 0.2, 1.5);
  EXPECT_NEAR(client.state().v_mps, 0.3, 0.002);
  EXPECT_NEAR(client.state().omega_radps, 0.2, 0.002);
  EXPECT_FALSE(client.state().cmd_stale);
  double x = 0;
  base.with([&](sim::Simulator& sim, ScoutMiniFirmware& fw) {
    EXPECT_DOUBLE_EQ(fw.v_mps(), 0.3);
    x = sim.world().latest().config.base.x_m;
  });
  EXPECT_GT(x, 0.2);
  EXPECT_GT(client.state().odom_x_m, 0.2);
  // Commands stop: the driver zeroes, the base stops, BASE_STATE says stale.
  std::size_t sent_before;
  {
    std::lock_guard<std::mutex> lock(m);
    sent_before = sent.size();
  }
  ASSERT_TRUE(client.wait_for(
      [](const porter::base_state_t& s) { return s.cmd_stale && s.v_mps == 0.0; }, 5.0));
  base.with([](sim::Simulator&, ScoutMiniFirmware& fw) { EXPECT_EQ(fw.v_mps(), 0.0); });
  std::lock_guard<std::mutex> lock(m);
  ASSERT_GT(sent.size(), sent_before);
  EXPECT_EQ(sent.back().v_mps, 0.0);
  EXPECT_EQ(driver.stop(), 0);
}

TEST_P(BaseNodeTest, EstopHoldsTheBaseUntilReleasedAndCommandedAgain) {
  const std::string lcm = lcm_url();
  const std::string can = can_spec(lcm, "node_estop");
  SimulatedBase base(can);
  ASSERT_TRUE(base.open()) << base.error();
  Client client(lcm);
  DriverProcess driver(test::node_config(can), lcm);
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0));
  client.stream(0.25, 0.0, 1.0);
  ASSERT_NEAR(client.state().v_mps, 0.25, 0.002);
  client.estop(true);
  // Commands keep coming; the base must stop and stay stopped.
  std::atomic<bool> streaming{true};
  std::thread tracker([&] {
    while (streaming.load()) {
      client.command(0.25, 0.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  EXPECT_TRUE(client.wait_for(
      [](const porter::base_state_t& s) { return s.estop_active && s.v_mps == 0.0; }, 5.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(client.state().v_mps, 0.0);
  streaming = false;
  tracker.join();
  client.estop(false);
  ASSERT_TRUE(client.wait_for([](const porter::base_state_t& s) { return !s.estop_active; }, 5.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(client.state().v_mps, 0.0) << "a release alone does not move the base";
  client.stream(0.25, 0.0, 1.0);
  EXPECT_NEAR(client.state().v_mps, 0.25, 0.002);
}

TEST_P(BaseNodeTest, ReEnablesAfterAPowerCycle) {
  const std::string lcm = lcm_url();
  const std::string can = can_spec(lcm, "node_power");
  SimulatedBase base(can);
  ASSERT_TRUE(base.open()) << base.error();
  Client client(lcm);
  DriverProcess driver(test::node_config(can), lcm);
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0));
  base.with([](sim::Simulator& sim, ScoutMiniFirmware&) {
    EXPECT_TRUE(sim.power_cycle("scout_mini", 0.6).ok);
  });
  EXPECT_TRUE(client.wait_for([](const porter::base_state_t& s) { return !s.link_ok; }, 5.0));
  // Back on: standby after boot, the driver sends 0x421 again, commands move the base.
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0));
  client.stream(0.2, 0.0, 1.5);
  EXPECT_NEAR(client.state().v_mps, 0.2, 0.002);
  base.with([](sim::Simulator&, ScoutMiniFirmware& fw) {
    EXPECT_EQ(fw.mode(), ControlMode::can);
    EXPECT_DOUBLE_EQ(fw.v_mps(), 0.2);
  });
}

TEST_P(BaseNodeTest, ReportsFaultsAndStreamsThatStop) {
  const std::string lcm = lcm_url();
  const std::string can = can_spec(lcm, "node_faults");
  SimulatedBase base(can);
  ASSERT_TRUE(base.open()) << base.error();
  Client client(lcm);
  DriverProcess driver(test::node_config(can), lcm);
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0));
  base.with([](sim::Simulator& sim, ScoutMiniFirmware&) {
    EXPECT_TRUE(sim.raise_error("scout_mini", error_bit::kMotor4Comm).ok);
  });
  EXPECT_TRUE(client.wait_for(
      [](const porter::base_state_t& s) {
        return s.fault_bits == error_bit::kMotor4Comm &&
               s.vehicle_state == porter::base_state_t::VEHICLE_EXCEPTION;
      },
      5.0));
  base.with([](sim::Simulator& sim, ScoutMiniFirmware&) {
    EXPECT_TRUE(sim.clear_errors("scout_mini").ok);
  });
  EXPECT_TRUE(client.wait_for(
      [](const porter::base_state_t& s) {
        return s.fault_bits == 0 && s.vehicle_state == porter::base_state_t::VEHICLE_NORMAL;
      },
      5.0));
  // Every feedback stream stopped: the link is lost, and comes back when they resume.
  const std::vector<std::uint32_t> streams = {0x211, 0x221, 0x251, 0x252, 0x253, 0x254, 0x261,
                                              0x262, 0x263, 0x264, 0x311, 0x361};
  base.with([&](sim::Simulator& sim, ScoutMiniFirmware&) {
    for (std::uint32_t id : streams) EXPECT_TRUE(sim.set_stream("scout_mini", id, false).ok);
  });
  EXPECT_TRUE(client.wait_for([](const porter::base_state_t& s) { return !s.link_ok; }, 5.0));
  base.with([&](sim::Simulator& sim, ScoutMiniFirmware&) {
    for (std::uint32_t id : streams) sim.set_stream("scout_mini", id, true);
  });
  EXPECT_TRUE(client.wait_for([](const porter::base_state_t& s) { return s.link_ok; }, 5.0));
}

TEST_P(BaseNodeTest, CleanShutdownLeavesTheBaseCommandedToZero) {
  const std::string lcm = lcm_url();
  const std::string can = can_spec(lcm, "node_shutdown");
  SimulatedBase base(can);
  ASSERT_TRUE(base.open()) << base.error();
  std::mutex m;
  std::vector<MotionCommand> sent;
  base.tap([&](const std::string&, const can::CanFrame& f, bool from_device) {
    MotionCommand c;
    if (!from_device && decode_motion_command(f, c) == DecodeStatus::ok) {
      std::lock_guard<std::mutex> lock(m);
      sent.push_back(c);
    }
  });
  Client client(lcm);
  auto driver = std::make_unique<DriverProcess>(test::node_config(can), lcm);
  ASSERT_TRUE(client.wait_for(in_can_mode, 10.0));
  std::atomic<bool> streaming{true};
  std::thread tracker([&] {
    while (streaming.load()) {
      client.command(0.3, 0.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(driver->stop(), 0);
  streaming = false;
  tracker.join();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last frame crosses
  std::lock_guard<std::mutex> lock(m);
  ASSERT_GT(sent.size(), 10u);
  EXPECT_DOUBLE_EQ(sent[sent.size() - 2].v_mps, 0.3) << "moving until the stop";
  EXPECT_EQ(sent.back().v_mps, 0.0) << "the last frame is a zero 0x111";
  base.with([](sim::Simulator&, ScoutMiniFirmware& fw) { EXPECT_EQ(fw.target().v_mps, 0.0); });
}

INSTANTIATE_TEST_SUITE_P(Transports, BaseNodeTest,
                         ::testing::Values(Transport{"memory", false}, Transport{"lcm", true}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace porter::scout_mini
