// porter-arm as a process, against a PiperFirmware hosted by this test on the LCM-carried arm
// bus (real time): it enables the arm, follows ARM_CMD, publishes ARM_STATE and HEARTBEAT,
// halts on ESTOP until released, re-enables after a power cycle, and on SIGTERM disables the
// arm and exits 0. The process is started and stopped by PID.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>

#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/piper/piper_firmware.hpp"

namespace porter::piper {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Ports no other test uses: the arm bus and the process's other channels.
const std::string kCanUrl = "udpm://239.255.76.67:7770?ttl=0";
const std::string kLcmUrl = "udpm://239.255.76.67:7771?ttl=0";

/// PiperFirmware on the LCM arm bus, stepped in real time every millisecond on its own thread.
class FirmwareHost {
 public:
  FirmwareHost()
      : bus_(can::open_can_bus("lcm:" + std::string(channels::kCanArm.name()) + "@" + kCanUrl, "porter-sim-test")) {
    EXPECT_TRUE(bus_->is_open()) << bus_->last_error();
    thread_ = std::thread([this] { loop(); });
  }
  ~FirmwareHost() {
    running_ = false;
    thread_.join();
  }
  PiperTruth truth() {
    std::lock_guard<std::mutex> lock(mutex_);
    return fw_.truth();
  }
  void with_firmware(const std::function<void(PiperFirmware&)>& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f(fw_);
  }

 private:
  void loop() {
    const auto start = Clock::now();
    auto next = start;
    std::vector<can::CanFrame> out;
    while (running_) {
      next += std::chrono::milliseconds(1);
      std::this_thread::sleep_until(next);
      const double t = std::chrono::duration<double>(Clock::now() - start).count();
      out.clear();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        can::CanFrame f;
        while (bus_->receive(f, 0) == can::CanStatus::ok) fw_.receive(f, t);
        fw_.advance(t, out);
      }
      for (const can::CanFrame& f : out) bus_->send(f);
      if (Clock::now() > next + std::chrono::milliseconds(50)) next = Clock::now();  // a stall: no burst
    }
  }

  std::unique_ptr<can::CanBus> bus_;
  PiperFirmware fw_;
  std::mutex mutex_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

class PorterArmProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("porter_arm_process_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    config_ = dir_ / "porter_arm.yaml";
    std::ifstream in(fs::path(PORTER_SOURCE_DIR) / "config/drivers/porter_arm.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    auto replace = [&](const std::string& from, const std::string& to) {
      const auto at = yaml.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      yaml.replace(at, from.size(), to);
    };
    replace("can_bus: lcm:CAN_ARM", "can_bus: \"lcm:CAN_ARM@" + kCanUrl + "\"");
    replace("lcm_url: \"\"", "lcm_url: \"" + kLcmUrl + "\"");
    replace("../robots/", (fs::path(PORTER_SOURCE_DIR) / "config/robots/").string());
    std::ofstream(config_) << yaml;
  }

  void TearDown() override {
    if (HasFailure()) std::cerr << "porter-arm log:\n" << log();
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    fs::remove_all(dir_);
  }

  void start() {
    const std::string log = (dir_ / "porter-arm.log").string();
    pid_ = ::fork();
    ASSERT_GE(pid_, 0);
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execl(PORTER_ARM_EXE, PORTER_ARM_EXE, "--config", config_.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }

  std::string log() const {
    std::ifstream in(dir_ / "porter-arm.log");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  fs::path dir_, config_;
  pid_t pid_ = -1;
};

/// Handles LCM until `done()` or `seconds` passed (a liveness bound, not a timing assertion).
bool wait_for(LcmBus& lcm, const std::function<bool()>& done, double seconds,
              const std::function<void()>& each_10ms = {}) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < deadline) {
    lcm.handle_timeout(10);
    if (each_10ms) each_10ms();
    if (done()) return true;
  }
  return done();
}

TEST_F(PorterArmProcess, EnablesFollowsStopsOnEstopRecoversAndDisablesOnSigterm) {
  FirmwareHost host;
  LcmBus lcm(kLcmUrl);
  ASSERT_TRUE(lcm.good());
  porter::arm_state_t state;
  int states = 0;
  lcm.subscribe(channels::kArmState, [&](const porter::arm_state_t& s) {
    state = s;
    ++states;
  });
  int heartbeats = 0;
  lcm.subscribe(channels::kHeartbeat, [&](const porter::process_heartbeat_t& h) {
    if (h.pid == pid_ && h.process == "porter-arm") ++heartbeats;
  });
  start();

  // Enable sequence.
  ASSERT_TRUE(wait_for(lcm, [&] { return states > 0 && state.enabled && state.ctrl_mode == 1; }, 20.0))
      << log();
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
  ASSERT_TRUE(wait_for(lcm, reached, 20.0, publish_cmd)) << log();
  ASSERT_TRUE(wait_for(lcm, [&] { return std::abs(state.q_rad[1] - 0.5) < 1e-3 && !state.cmd_stale; }, 5.0,
                       publish_cmd));
  EXPECT_FALSE(state.fault) << state.faults;
  EXPECT_GT(heartbeats, 0);

  // ESTOP: the firmware is stopped and stays so while commands keep coming.
  porter::estop_t estop;
  estop.active = true;
  estop.source = "test";
  estop.reason = "process test";
  lcm.publish(channels::kEstop, estop);
  // ARM_STATE names the arm's own report of the e-stop among its faults.
  ASSERT_TRUE(wait_for(lcm,
                       [&] {
                         return host.truth().estop && state.estop_active &&
                                state.faults.find("emergency_stop") != std::string::npos;
                       },
                       10.0, publish_cmd))
      << log();
  cmd.q_rad[0] = -0.3;
  wait_for(lcm, [] { return false; }, 0.3, publish_cmd);
  EXPECT_NEAR(host.truth().q_rad[0], 0.3, 1e-3);
  estop.active = false;
  lcm.publish(channels::kEstop, estop);
  ASSERT_TRUE(wait_for(lcm, [&] { return !host.truth().estop && reached(); }, 20.0, publish_cmd)) << log();

  // Power cycle: porter-arm re-runs the enable sequence.
  host.with_firmware([](PiperFirmware& fw) { fw.power_cycle(); });
  cmd.q_rad[0] = 0.0;
  ASSERT_TRUE(wait_for(lcm, reached, 20.0, publish_cmd)) << log();
  EXPECT_EQ(host.truth().ctrl_mode, 1);

  // SIGTERM: disable, then exit 0.
  ASSERT_EQ(::kill(pid_, SIGTERM), 0);
  int status = 0;
  pid_t done = 0;
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  while ((done = ::waitpid(pid_, &status, WNOHANG)) == 0 && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(done, pid_) << "porter-arm did not exit after SIGTERM\n" << log();
  pid_ = -1;
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << log();
  for (bool enabled : host.truth().joint_enabled) EXPECT_FALSE(enabled);
  const std::string text = log();
  EXPECT_NE(text.find("SIGINT/SIGTERM: disabling the arm"), std::string::npos) << text;
  EXPECT_NE(text.find("every joint reports disabled"), std::string::npos) << text;
  EXPECT_NE(text.find("ESTOP active (test: process test)"), std::string::npos) << text;
  EXPECT_NE(text.find("re-running the enable sequence"), std::string::npos) << text;
}

}  // namespace
}  // namespace porter::piper
