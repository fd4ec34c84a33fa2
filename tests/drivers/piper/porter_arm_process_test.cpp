// porter-arm as a process, against a PiperFirmware hosted by this test on the LCM-carried arm
// bus (real time): it enables the arm, follows ARM_CMD, publishes ARM_STATE and HEARTBEAT,
// halts on ESTOP until released, re-enables after a power cycle, and on SIGTERM disables the
// arm and exits 0. The process is started and stopped by PID.
#include <gtest/gtest.h>

#include <cmath>

#include "arm_process_support.hpp"
#include "private_lcm_url.hpp"

namespace porter::piper::test {
namespace {

// Free ports (udpm traffic is host-wide): the arm bus and the process's other channels.
const std::string kCanUrl = porter::test::private_lcm_url();
const std::string kLcmUrl = porter::test::private_lcm_url();

TEST(PorterArmProcess, EnablesFollowsStopsOnEstopRecoversAndDisablesOnSigterm) {
  FirmwareHost host(kCanUrl);
  ASSERT_TRUE(host.bus_open()) << host.bus_error();
  LcmBus lcm(kLcmUrl);
  ASSERT_TRUE(lcm.good());
  porter::arm_state_t state;
  int states = 0;
  lcm.subscribe(channels::kArmState, [&](const porter::arm_state_t& s) {
    state = s;
    ++states;
  });
  ArmProcess arm(PORTER_ARM_EXE, PORTER_SOURCE_DIR, kCanUrl, kLcmUrl, "process_test");
  ASSERT_TRUE(arm.started());
  int heartbeats = 0;
  lcm.subscribe(channels::kHeartbeat, [&](const porter::process_heartbeat_t& h) {
    if (h.pid == arm.pid() && h.process == "porter-arm") ++heartbeats;
  });

  // Enable sequence.
  ASSERT_TRUE(wait_for(lcm, [&] { return states > 0 && state.enabled && state.ctrl_mode == 1; }, 20.0))
      << arm.log();
  EXPECT_TRUE(state.link_ok);
  EXPECT_TRUE(state.cmd_stale);  // no ARM_CMD yet: holding

  // Follow ARM_CMD at 100 Hz.
  porter::arm_cmd_t cmd;
  cmd.enabled = true;
  cmd.num_joints = 6;
  cmd.q_rad = {0.3, 0.5, -0.4, 0.2, 0.1, -0.2};
  cmd.qd_radps.assign(6, 0.0);
  cmd.speed_pct = 100;
  cmd.plan_id = -1;
  cmd.source = "porter-arm-process-test";
  auto publish_cmd = [&] { lcm.publish(channels::kArmCmd, cmd); };
  auto reached = [&] {
    const PiperTruth t = host.truth();
    for (int j = 0; j < kNumJoints; ++j) {
      if (std::abs(t.q_rad[j] - cmd.q_rad[j]) > 1e-3) return false;
    }
    return true;
  };
  ASSERT_TRUE(wait_for(lcm, reached, 20.0, publish_cmd)) << arm.log();
  ASSERT_TRUE(wait_for(lcm, [&] { return std::abs(state.q_rad[1] - 0.5) < 1e-3 && !state.cmd_stale; }, 5.0,
                       publish_cmd));
  EXPECT_FALSE(state.fault) << state.faults;
  EXPECT_GT(heartbeats, 0);

  // ESTOP: the firmware is stopped and stays so while commands keep coming; ARM_STATE names
  // the arm's own report of the e-stop among its faults.
  porter::estop_t estop;
  estop.active = true;
  estop.source = "test";
  estop.reason = "process test";
  lcm.publish(channels::kEstop, estop);
  ASSERT_TRUE(wait_for(lcm,
                       [&] {
                         return host.truth().estop && state.estop_active &&
                                state.faults.find("emergency_stop") != std::string::npos;
                       },
                       10.0, publish_cmd))
      << arm.log();
  cmd.q_rad[0] = -0.3;
  wait_for(lcm, [] { return false; }, 0.3, publish_cmd);
  EXPECT_NEAR(host.truth().q_rad[0], 0.3, 1e-3);
  estop.active = false;
  lcm.publish(channels::kEstop, estop);
  ASSERT_TRUE(wait_for(lcm, [&] { return !host.truth().estop && reached(); }, 20.0, publish_cmd)) << arm.log();

  // Power cycle: porter-arm re-runs the enable sequence.
  host.with_firmware([](PiperFirmware& fw) { fw.power_cycle(); });
  cmd.q_rad[0] = 0.0;
  ASSERT_TRUE(wait_for(lcm, reached, 20.0, publish_cmd)) << arm.log();
  EXPECT_EQ(host.truth().ctrl_mode, 1);

  // SIGTERM: disable, then exit 0.
  ASSERT_EQ(arm.terminate(10.0), 0) << arm.log();
  for (bool enabled : host.truth().joint_enabled) EXPECT_FALSE(enabled);
  const std::string text = arm.log();
  EXPECT_NE(text.find("SIGINT/SIGTERM: disabling the arm"), std::string::npos) << text;
  EXPECT_NE(text.find("every joint reports disabled"), std::string::npos) << text;
  EXPECT_NE(text.find("ESTOP active (test: process test)"), std::string::npos) << text;
  EXPECT_NE(text.find("re-running the enable sequence"), std::string::npos) << text;
}

}  // namespace
}  // namespace porter::piper::test
