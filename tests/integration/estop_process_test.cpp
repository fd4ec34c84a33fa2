// E-stop across processes: porter-tracker runs as a process on a private udpm port, fed by this
// test with ROBOT_STATE at 100 Hz and a straight TRAJECTORY; once it commands motion, ESTOP
// (active) must turn BASE_CMD and ARM_CMD disabled within one control period (at most one more
// enabled command after the e-stop is received), they must stay disabled while the e-stop is
// held, and a release (active = false) alone must not restart motion (it needs a new trajectory).
// The drivers' own e-stop handling has its tests (scout_mini node, porter-arm process).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/runtime/clock.hpp"
#include "private_lcm_url.hpp"
#include "trajectory_fixtures.hpp"

namespace porter {
namespace {

TEST(EstopProcesses, TrackerDisablesBaseAndArmWithinOnePeriodAndStaysStopped) {
  const std::string url = test::private_lcm_url();
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open("estop_tracker.log", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, STDERR_FILENO);
    execl(PORTER_TRACKER_BIN, PORTER_TRACKER_BIN, "--lcm-url", url.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(pid, 0);
  LcmBus bus(url);
  ASSERT_TRUE(bus.good());
  int enabled_after_estop = -1, disabled_after_estop = 0, enabled_commands = 0, arm_enabled_after = 0;
  bool estop_sent = false;
  bus.subscribe(channels::kBaseCmd, [&](const base_cmd_t& m) {
    if (!estop_sent) {
      enabled_commands += m.enabled ? 1 : 0;
      return;
    }
    if (m.enabled && disabled_after_estop == 0) ++enabled_after_estop;
    if (m.enabled && disabled_after_estop > 0) enabled_after_estop = 1000;  // motion resumed
    if (!m.enabled) ++disabled_after_estop;
  });
  bus.subscribe(channels::kArmCmd, [&](const arm_cmd_t& m) {
    if (estop_sent && disabled_after_estop > 0 && m.enabled) ++arm_enabled_after;
  });
  robot_state_t s{};
  s.frame_id = "world";
  s.num_joints = 6;
  s.q_rad.assign(6, 0.0);
  s.qd_radps.assign(6, 0.0);
  s.pose_valid = s.base_valid = s.arm_valid = true;
  s.pose_source = robot_state_t::POSE_SIM_TRUTH;
  auto spin = [&](double seconds) {
    const double end = runtime::mono_s() + seconds;
    while (runtime::mono_s() < end) {
      s.utime = runtime::wall_utime();
      bus.publish(channels::kRobotState, s);
      bus.handle_timeout(10);
    }
  };
  spin(1.0);  // the tracker is up and sees a valid state
  const Trajectory t = test::straight(0.3, 20.0, 1);
  minco_trajectory_t msg = to_msg(t, runtime::wall_utime() + 50'000, 1, "world", "");
  msg.utime = runtime::wall_utime();
  bus.publish(channels::kTrajectory, msg);
  spin(1.0);
  ASSERT_GT(enabled_commands, 20) << "the tracker must be tracking before the e-stop";
  estop_t e{};
  e.utime = runtime::wall_utime();
  e.active = true;
  e.source = "estop_process_test";
  e.reason = "test";
  bus.publish(channels::kEstop, e);
  estop_sent = true;
  enabled_after_estop = 0;
  spin(1.0);
  EXPECT_LE(enabled_after_estop, 1) << "enabled BASE_CMDs after the e-stop (at most the one in flight)";
  EXPECT_GT(disabled_after_estop, 50);
  EXPECT_EQ(arm_enabled_after, 0);
  e.active = false;
  e.utime = runtime::wall_utime();
  bus.publish(channels::kEstop, e);
  spin(0.5);
  EXPECT_LE(enabled_after_estop, 1) << "a release alone restarted motion";
  kill(pid, SIGTERM);
  int status = 0;
  for (int i = 0; i < 500 && waitpid(pid, &status, WNOHANG) != pid; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (kill(pid, 0) == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

}  // namespace
}  // namespace porter
