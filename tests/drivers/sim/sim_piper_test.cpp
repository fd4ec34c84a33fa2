// The Piper firmware model hosted by porter-sim (SimProcess built from the shipped config, buses
// in memory, the LiDAR off), driven by the arm driver's logic (ArmDriver) in lockstep on the
// other end of the arm bus: the enable sequence, joint targets moving the world's ground truth,
// and the SIM_COMMAND faults on the arm (stop a stream, raise an error, power cycle, drop the
// bus), each seen by the driver as on the real arm and recovered from.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <vector>

#include "porter/can/memory_bus.hpp"
#include "porter/piper/arm_driver.hpp"
#include "porter/piper/commands.hpp"
#include "porter/piper/protocol.hpp"
#include "sim_config.hpp"
#include "sim_piper.hpp"
#include "sim_process.hpp"

namespace porter::sim {
namespace {

const std::string kSource = PORTER_SOURCE_DIR;

SimConfig memory_config(const std::string& tag) {
  std::ifstream in(kSource + "/config/drivers/porter_sim.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex(R"(\.\./)"), kSource + "/config/");
  text = std::regex_replace(text, std::regex("lcm:CAN_BASE"), "memory:piper_test_base_" + tag);
  text = std::regex_replace(text, std::regex("lcm:CAN_ARM"), "memory:piper_test_arm_" + tag);
  text = std::regex_replace(text, std::regex("  enabled: true"), "  enabled: false");
  const auto dir = std::filesystem::temp_directory_path() / "porter_sim_piper_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / (tag + ".yaml")).string();
  std::ofstream(path) << text;
  return load_sim_config(path);
}

piper::ArmDriverParams driver_params(const World& world) {
  piper::ArmDriverParams p;
  for (int j = 0; j < piper::kNumJoints; ++j) {
    p.lower_rad[j] = world.robot().joints[j].lower_rad;
    p.upper_rad[j] = world.robot().joints[j].upper_rad;
  }
  return p;
}

/// porter-sim's body and an ArmDriver on the other end of the in-memory arm bus, stepped
/// together: the simulator every 1 ms, the driver every 5 ms (porter-arm's 200 Hz).
struct Rig {
  explicit Rig(const std::string& tag)
      : config(memory_config(tag)),
        lcm("memq://"),
        process(config, lcm),
        driver(driver_params(process.simulator().world())),
        bus(can::MemoryBus::open("piper_test_arm_" + tag)) {}

  Simulator& sim() { return process.simulator(); }
  const piper::PiperFirmware& firmware() {
    return static_cast<SimulatedPiper*>(sim().node("piper"))->firmware();
  }

  void tick() {
    ++k;
    const double t = k * 1e-3;
    can::CanFrame f;
    while (bus->receive(f, 0) == can::CanStatus::ok) driver.on_frame(f, t);
    if (k % 5 == 0) {
      if (command) driver.on_command(*command, t);
      out.clear();
      driver.step(t, out);
      for (const can::CanFrame& c : out) bus->send(c);
    }
    sim().step_to(t);
  }
  bool run_until(const std::function<bool()>& done, double max_s) {
    for (long i = 0; i < std::lround(max_s / 1e-3); ++i) {
      if (done()) return true;
      tick();
    }
    return done();
  }
  bool active() { return driver.phase() == piper::ArmPhase::active; }
  bool reached(const piper::ArmCommand& c, double tol = 1e-3) {
    const JointVector q = sim().world().latest().config.q_rad;
    for (int j = 0; j < piper::kNumJoints; ++j) {
      if (std::abs(q[j] - c.q_rad[j]) > tol) return false;
    }
    return true;
  }

  SimConfig config;
  LcmBus lcm;
  SimProcess process;
  piper::ArmDriver driver;
  std::unique_ptr<can::CanBus> bus;
  std::optional<piper::ArmCommand> command;
  std::vector<can::CanFrame> out;
  long k = 0;
};

TEST(SimPiper, TheDefaultConfigHostsBothFirmwareModels) {
  const SimConfig c = load_sim_config(kSource + "/config/drivers/porter_sim.yaml");
  ASSERT_EQ(c.buses.size(), 2u);
  EXPECT_EQ(c.buses[0].devices, std::vector<std::string>{"scout_mini"});
  EXPECT_EQ(c.buses[1].name, "arm");
  EXPECT_EQ(c.buses[1].devices, std::vector<std::string>{"piper"});
  EXPECT_TRUE(c.lidar.enabled);
}

TEST(SimPiper, StreamGroupsByCanId) {
  using piper::FeedbackStream;
  EXPECT_EQ(SimulatedPiper::stream_of(0x2A1), FeedbackStream::status);
  EXPECT_EQ(SimulatedPiper::stream_of(0x2A3), FeedbackStream::end_pose);
  EXPECT_EQ(SimulatedPiper::stream_of(0x2A5), FeedbackStream::joint_angles);
  EXPECT_EQ(SimulatedPiper::stream_of(0x2A7), FeedbackStream::joint_angles);
  EXPECT_EQ(SimulatedPiper::stream_of(0x2A8), FeedbackStream::gripper);
  EXPECT_EQ(SimulatedPiper::stream_of(0x256), FeedbackStream::high_speed);
  EXPECT_EQ(SimulatedPiper::stream_of(0x261), FeedbackStream::low_speed);
  EXPECT_FALSE(SimulatedPiper::stream_of(0x257).has_value());
  EXPECT_FALSE(SimulatedPiper::stream_of(0x155).has_value());
}

TEST(SimPiper, TheDriverEnablesTheArmAndItsJointsMoveTheWorld) {
  Rig rig("move");
  const JointVector start = rig.sim().world().scene().start.q_rad;
  ASSERT_TRUE(rig.run_until([&] { return rig.active(); }, 3.0));
  // Before any target the arm holds the scene's start angles (to the wire's 0.001 deg: the
  // driver holds at the angles it measured).
  EXPECT_LT((rig.sim().world().latest().config.q_rad - start).cwiseAbs().maxCoeff(), 2e-5);
  piper::ArmCommand c;
  c.q_rad = {0.5, 1.0, -1.2, 0.3, -0.4, 0.2};
  c.speed_pct = 100;
  rig.command = c;
  const double t0 = rig.sim().time_s();
  ASSERT_TRUE(rig.run_until([&] { return rig.reached(c); }, 5.0));
  // 3 rad/s with 10 rad/s^2: the largest move (0.6 rad) takes at least 0.2 s.
  EXPECT_GT(rig.sim().time_s() - t0, 0.2);
  // robot_at() interpolates the recorded joints; the truth agrees with the firmware's.
  const RobotSample s = rig.sim().world().robot_at(rig.sim().time_s());
  for (int j = 0; j < piper::kNumJoints; ++j) {
    EXPECT_NEAR(s.config.q_rad[j], rig.firmware().truth().q_rad[j], 1e-12);
  }
  // A target outside the joint range is clamped by the driver: nothing leaves the range.
  c.q_rad[1] = 9.0;
  rig.command = c;
  rig.run_until([] { return false; }, 2.0);
  EXPECT_LE(rig.sim().world().latest().config.q_rad[1], rig.sim().world().robot().joints[1].upper_rad + 1e-9);
}

TEST(SimPiper, FaultsOnTheArmAreSeenByTheDriverAndRecovered) {
  Rig rig("faults");
  ASSERT_TRUE(rig.run_until([&] { return rig.active(); }, 3.0));
  piper::ArmCommand c;
  c.q_rad = {0.2, 0.8, -0.8, 0.0, 0.3, 0.0};
  c.speed_pct = 100;
  rig.command = c;
  ASSERT_TRUE(rig.run_until([&] { return rig.reached(c); }, 5.0));

  // The joint-angle stream stops: the link is lost (the status frame alone does not keep it).
  SimCommand stop{SimCommand::Kind::stop_stream, "piper", 0x2A5};
  ASSERT_TRUE(rig.sim().apply(stop).ok);
  EXPECT_TRUE(rig.run_until([&] { return !rig.driver.status(rig.sim().time_s()).link_ok; }, 1.0));
  SimCommand resume{SimCommand::Kind::resume_stream, "piper", 0x2A6};
  ASSERT_TRUE(rig.sim().apply(resume).ok);
  EXPECT_TRUE(rig.run_until([&] { return rig.active(); }, 3.0));
  SimCommand unknown{SimCommand::Kind::stop_stream, "piper", 0x123};
  EXPECT_FALSE(rig.sim().apply(unknown).ok);

  // An error code raised on the arm shows among the driver's faults until cleared.
  SimCommand raise{SimCommand::Kind::raise_error, "piper"};
  raise.error_code = 0x0001;  // joint 1 angle limit
  ASSERT_TRUE(rig.sim().apply(raise).ok);
  EXPECT_TRUE(rig.run_until([&] { return (rig.driver.feedback().err_code & 0x0001) != 0; }, 0.5));
  raise.error_code = 0x10000;
  EXPECT_FALSE(rig.sim().apply(raise).ok) << "the error word has 16 bits";
  ASSERT_TRUE(rig.sim().apply({SimCommand::Kind::clear_errors, "piper"}).ok);
  EXPECT_TRUE(rig.run_until([&] { return rig.driver.feedback().err_code == 0; }, 0.5));

  // Power cycle: off (silent) for 0.3 s, back disabled in standby; the driver re-enables it and
  // the next target is followed.
  SimCommand cycle{SimCommand::Kind::power_cycle, "piper"};
  cycle.duration_s = 0.3;
  ASSERT_TRUE(rig.sim().apply(cycle).ok);
  EXPECT_FALSE(rig.firmware().truth().powered);
  const double off_at = rig.sim().time_s();
  ASSERT_TRUE(rig.run_until([&] { return rig.firmware().truth().powered; }, 1.0));
  EXPECT_NEAR(rig.sim().time_s() - off_at, 0.3, 0.0015);
  EXPECT_EQ(rig.firmware().truth().ctrl_mode, 0) << "standby after power-on";
  c.q_rad[0] = -0.4;
  rig.command = c;
  EXPECT_TRUE(rig.run_until([&] { return rig.reached(c); }, 5.0));
  EXPECT_EQ(rig.firmware().truth().ctrl_mode, piper::ctrl_mode::kCan);

  // The arm bus drops: nothing crosses it, the driver loses the link; restored, it goes on.
  ASSERT_TRUE(rig.sim().apply({SimCommand::Kind::drop_bus, "arm"}).ok);
  EXPECT_TRUE(rig.run_until([&] { return !rig.driver.status(rig.sim().time_s()).link_ok; }, 1.0));
  ASSERT_TRUE(rig.sim().apply({SimCommand::Kind::restore_bus, "arm"}).ok);
  c.q_rad[0] = 0.4;
  rig.command = c;
  EXPECT_TRUE(rig.run_until([&] { return rig.reached(c); }, 5.0));
}

}  // namespace
}  // namespace porter::sim
