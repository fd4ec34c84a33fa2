// porter-state and porter-tracker as processes on a private udpm port, fed by this test: a
// simulated base (a unicycle obeying BASE_CMD, reporting BASE_STATE at 50 Hz) and arm (obeying
// ARM_CMD, reporting ARM_STATE at 100 Hz); a TRAJECTORY is sent and the robot must follow it to
// its end; then BASE_STATE stops and BASE_CMD must turn disabled. Processes are started here and
// stopped by PID.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/msg/trajectory_msg.hpp"
#include "porter/runtime/clock.hpp"
#include "trajectory_fixtures.hpp"
#include "private_lcm_url.hpp"

namespace porter {
namespace {

// A free port: udpm traffic is host-wide, other runs of this test must not cross.
const std::string kUrl = test::private_lcm_url();

// A child process, SIGTERMed (then SIGKILLed) when the test ends whatever happens.
class Child {
 public:
  Child(const std::string& binary, const std::vector<std::string>& args, const std::string& log) {
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) dup2(fd, STDERR_FILENO);
      std::vector<char*> argv{const_cast<char*>(binary.c_str())};
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(binary.c_str(), argv.data());
      _exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !reaped_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  pid_t pid() const { return pid_; }
  /// SIGTERM, then waits up to 5 s; returns the exit status (-1 when it had to be killed).
  int stop() {
    kill(pid_, SIGTERM);
    for (int i = 0; i < 500; ++i) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
};

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(TrackerProcesses, StateAndTrackerDriveASimulatedBase) {
  // File names carry the pid: another run of this test at the same time (another build tree on
  // the same machine) must not overwrite the logs and the stats file this one reads.
  const std::string dir = testing::TempDir() + "/porter_tracker_multiprocess_" +
                          std::to_string(::getpid());
  ::mkdir(dir.c_str(), 0755);
  // The shipped tracker config, without SCHED_FIFO (tests share the machine), robot path absolute.
  std::string config = read_file(std::string(PORTER_SOURCE_DIR) +
                                 "/config/tracker/porter_tracker.yaml");
  config.replace(config.find("sched_fifo: true"), 16, "sched_fifo: false");
  config.replace(config.find("robot: ../robots/"), 17,
                 "robot: " + std::string(PORTER_SOURCE_DIR) + "/config/robots/");
  const std::string config_path = dir + "/porter_tracker_multiprocess.yaml";
  std::ofstream(config_path) << config;

  LcmBus bus(kUrl);
  ASSERT_TRUE(bus.good());
  robot_state_t last_state;
  int states = 0;
  base_cmd_t last_cmd;
  int cmds = 0;
  arm_cmd_t last_arm;
  bool arm_cmd = false;
  bool finished_seen = false;
  int estop_reports = 0;
  bus.subscribe(channels::kRobotState, [&](const robot_state_t& m) { last_state = m; ++states; });
  bus.subscribe(channels::kBaseCmd, [&](const base_cmd_t& m) { last_cmd = m; ++cmds; });
  bus.subscribe(channels::kArmCmd, [&](const arm_cmd_t& m) { last_arm = m; arm_cmd = true; });
  bus.subscribe(channels::kTrackerStatus, [&](const tracker_status_t& m) {
    if (m.state == tracker_status_t::STATE_FINISHED) finished_seen = true;
    if (m.state == tracker_status_t::STATE_ESTOP) ++estop_reports;
  });

  Child state(PORTER_STATE_BIN, {"--lcm-url", kUrl}, dir + "/porter_state_multiprocess.log");
  const std::string stats_path = dir + "/porter_tracker_multiprocess_stats.json";
  std::remove(stats_path.c_str());
  Child tracker(PORTER_TRACKER_BIN,
                {"--lcm-url", kUrl, "--config", config_path, "--stats-out", stats_path},
                dir + "/porter_tracker_multiprocess.log");
  ASSERT_GT(state.pid(), 0);
  ASSERT_GT(tracker.pid(), 0);

  // The simulated robot.
  BasePose pose;
  JointVector q = JointVector::Zero();
  bool feed_base = true;
  std::int64_t last_sim = runtime::wall_utime(), last_base = 0, last_arm_pub = 0;
  auto run = [&](double seconds, const std::function<bool()>& until) {
    const std::int64_t end = runtime::wall_utime() + static_cast<std::int64_t>(seconds * 1e6);
    while (runtime::wall_utime() < end) {
      bus.handle_pending();
      const std::int64_t now = runtime::wall_utime();
      const double dt = static_cast<double>(now - last_sim) * 1e-6;
      last_sim = now;
      if (cmds > 0 && last_cmd.enabled && now - last_cmd.utime < 200'000) {
        pose.x_m += last_cmd.v_mps * std::cos(pose.yaw_rad) * dt;
        pose.y_m += last_cmd.v_mps * std::sin(pose.yaw_rad) * dt;
        pose.yaw_rad += last_cmd.omega_radps * dt;
      }
      if (arm_cmd && last_arm.enabled) {
        for (int j = 0; j < 6; ++j) q[j] = last_arm.q_rad[static_cast<std::size_t>(j)];
      }
      if (feed_base && now - last_base >= 20'000) {
        base_state_t b{};
        b.utime = now;
        b.odom_x_m = pose.x_m;
        b.odom_y_m = pose.y_m;
        b.odom_yaw_rad = pose.yaw_rad;
        b.v_mps = last_cmd.enabled ? last_cmd.v_mps : 0.0;
        b.omega_radps = last_cmd.enabled ? last_cmd.omega_radps : 0.0;
        b.num_motors = 0;
        b.link_ok = true;
        bus.publish(channels::kBaseState, b);
        last_base = now;
      }
      if (now - last_arm_pub >= 10'000) {
        arm_state_t a{};
        a.utime = now;
        a.num_joints = 6;
        a.q_rad.assign(q.data(), q.data() + 6);
        a.qd_radps.assign(6, 0.0);
        a.effort_nm.assign(6, 0.0);
        a.motor_temperature_c.assign(6, 30.0);
        a.joint_status_bits.assign(6, 0);
        a.joint_enabled.assign(6, true);
        a.enabled = a.link_ok = true;
        bus.publish(channels::kArmState, a);
        last_arm_pub = now;
      }
      if (until && until()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  };

  // 1. porter-state fuses the inputs; porter-tracker is idle (commands disabled).
  ASSERT_TRUE(run(10.0, [&] {
    return states > 0 && last_state.base_valid && last_state.arm_valid && last_state.pose_valid &&
           cmds > 0;
  })) << read_file(dir + "/porter_state_multiprocess.log")
      << read_file(dir + "/porter_tracker_multiprocess.log");
  EXPECT_EQ(last_state.pose_source, robot_state_t::POSE_WHEEL_ODOM);
  EXPECT_EQ(last_state.num_joints, 6);
  EXPECT_FALSE(last_cmd.enabled);
  EXPECT_EQ(last_cmd.plan_id, -1);

  // 2. A trajectory: 0.4 m/s along x with joint 1 to 0.5 rad, starting 0.3 s from now.
  const Trajectory traj = test::straight(0.4, 1.0, +1);
  const std::int64_t start = runtime::wall_utime() + 300'000;
  minco_trajectory_t msg = to_msg(traj, start, 1, "world", "");
  msg.utime = runtime::wall_utime();
  bus.publish(channels::kTrajectory, msg);
  double max_v = 0.0;
  run(0.25, {});
  EXPECT_FALSE(last_cmd.enabled);  // not before its start
  run(traj.total_duration_s() + 0.6, [&] {
    max_v = std::max(max_v, last_cmd.v_mps);
    return false;
  });
  EXPECT_TRUE(finished_seen);
  EXPECT_GT(max_v, 0.3);
  const TrajVector end = traj.position(traj.total_duration_s());
  EXPECT_NEAR(pose.x_m, end[0], 0.05) << read_file(dir + "/porter_tracker_multiprocess.log");
  EXPECT_NEAR(pose.y_m, 0.0, 0.02);
  EXPECT_NEAR(q[0], end[2], 1e-9);  // the arm holds the final joint angles
  EXPECT_NEAR(last_state.x_m, pose.x_m, 0.01);
  EXPECT_TRUE(last_cmd.enabled);  // holding at the end
  EXPECT_EQ(last_cmd.v_mps, 0.0);
  EXPECT_EQ(last_cmd.plan_id, 1);

  // 3. The base driver goes silent: ROBOT_STATE flags it and the commands turn disabled.
  feed_base = false;
  EXPECT_TRUE(run(1.0, [&] { return !last_state.base_valid && !last_cmd.enabled; }));

  // 4. It comes back: valid again (and porter-state survived the gap).
  feed_base = true;
  EXPECT_TRUE(run(1.0, [&] { return last_state.base_valid; }));

  // 5. ESTOP: the commands turn disabled and TRACKER_STATUS reports ESTOP; the release leaves
  //    the tracker without a trajectory (commands stay disabled).
  EXPECT_TRUE(run(1.0, [&] { return last_cmd.enabled; }));  // holding the end again
  estop_t estop{};
  estop.utime = runtime::wall_utime();
  estop.active = true;
  estop.source = "multiprocess-test";
  estop.reason = "stop button";
  bus.publish(channels::kEstop, estop);
  EXPECT_TRUE(run(2.0, [&] { return !last_cmd.enabled && estop_reports > 0; }));
  estop.utime = runtime::wall_utime();
  estop.active = false;
  estop.reason.clear();
  bus.publish(channels::kEstop, estop);
  const int cmds_at_release = cmds;
  run(0.3, {});
  EXPECT_GT(cmds, cmds_at_release);
  EXPECT_FALSE(last_cmd.enabled);
  EXPECT_EQ(last_cmd.plan_id, -1);

  EXPECT_EQ(tracker.stop(), 0);
  EXPECT_EQ(state.stop(), 0);
  const std::string log = read_file(dir + "/porter_tracker_multiprocess.log");
  EXPECT_NE(log.find("plan 1 accepted"), std::string::npos) << log;
  EXPECT_NE(log.find("state FINISHED"), std::string::npos) << log;
  EXPECT_NE(log.find("period jitter"), std::string::npos) << log;
  EXPECT_NE(log.find("ESTOP engaged by multiprocess-test (stop button)"), std::string::npos) << log;
  EXPECT_NE(log.find("ESTOP released by multiprocess-test"), std::string::npos) << log;
  const std::string stats = read_file(stats_path);
  EXPECT_NE(stats.find("\"period_jitter_us\""), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"command_latency_us\""), std::string::npos) << stats;
  if (!HasFailure()) std::filesystem::remove_all(dir);  // kept for a look when it failed
}

}  // namespace
}  // namespace porter
