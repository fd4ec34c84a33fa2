#pragma once
// Support for running porter-arm as a process against a simulated arm (the process test and
// porter-bench-arm): a PiperFirmware hosted on the LCM-carried arm bus in real time, and a
// porter-arm started with a config derived from the shipped one and stopped by PID.
// No GoogleTest here: failures come back as values.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/piper/piper_firmware.hpp"

namespace porter::piper::test {

using Clock = std::chrono::steady_clock;

/// PiperFirmware on the LCM arm bus at `can_url`, stepped in real time every millisecond on its
/// own thread. Keeps the frames it received whose ID `keep` accepts (with their sender's
/// utime), for measurements.
class FirmwareHost {
 public:
  explicit FirmwareHost(const std::string& can_url, std::function<bool(std::uint32_t)> keep = {})
      : bus_(can::open_can_bus("lcm:" + std::string(channels::kCanArm.name()) + "@" + can_url, "porter-sim-test")),
        keep_(std::move(keep)) {
    thread_ = std::thread([this] { loop(); });
  }
  ~FirmwareHost() {
    running_ = false;
    thread_.join();
  }
  bool bus_open() const { return bus_->is_open(); }
  std::string bus_error() const { return bus_->last_error(); }
  PiperTruth truth() {
    std::lock_guard<std::mutex> lock(mutex_);
    return fw_.truth();
  }
  void with_firmware(const std::function<void(PiperFirmware&)>& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f(fw_);
  }
  /// Frames kept since the last call (oldest first).
  std::vector<can::CanFrame> take_kept() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<can::CanFrame> out;
    out.swap(kept_);
    return out;
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
        while (bus_->receive(f, 0) == can::CanStatus::ok) {
          fw_.receive(f, t);
          if (keep_ && keep_(f.id) && kept_.size() < 1000000) kept_.push_back(f);
        }
        fw_.advance(t, out);
      }
      for (const can::CanFrame& f : out) bus_->send(f);
      if (Clock::now() > next + std::chrono::milliseconds(50)) next = Clock::now();  // after a stall, no burst
    }
  }

  std::unique_ptr<can::CanBus> bus_;
  std::function<bool(std::uint32_t)> keep_;
  PiperFirmware fw_;
  std::vector<can::CanFrame> kept_;
  std::mutex mutex_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

/// porter-arm started from `exe` with the shipped config, bus and LCM URLs replaced, in a
/// scratch directory (its log: log()). Killed (SIGKILL) on destruction if still running.
class ArmProcess {
 public:
  ArmProcess(const std::string& exe, const std::string& source_dir, const std::string& can_url,
             const std::string& lcm_url, const std::string& tag)
      : dir_(std::filesystem::temp_directory_path() / ("porter_arm_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    std::ifstream in(std::filesystem::path(source_dir) / "config/drivers/porter_arm.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    ok_ = replace(yaml, "can_bus: lcm:CAN_ARM", "can_bus: \"lcm:CAN_ARM@" + can_url + "\"") &&
          replace(yaml, "lcm_url: \"\"", "lcm_url: \"" + lcm_url + "\"") &&
          replace(yaml, "../robots/", (std::filesystem::path(source_dir) / "config/robots/").string());
    const std::string config = (dir_ / "porter_arm.yaml").string();
    std::ofstream(config) << yaml;
    const std::string log = (dir_ / "porter-arm.log").string();
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execl(exe.c_str(), exe.c_str(), "--config", config.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~ArmProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    std::filesystem::remove_all(dir_);
  }
  bool started() const { return ok_ && pid_ > 0; }
  pid_t pid() const { return pid_; }
  std::string log() const {
    std::ifstream in(dir_ / "porter-arm.log");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// Sends SIGTERM and waits up to `seconds` for the exit; the exit status, or -1 when it did
  /// not exit normally in time.
  int terminate(double seconds) {
    if (pid_ <= 0 || ::kill(pid_, SIGTERM) != 0) return -1;
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    int status = 0;
    pid_t done = 0;
    while ((done = ::waitpid(pid_, &status, WNOHANG)) == 0 && Clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (done != pid_) return -1;
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  static bool replace(std::string& text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos) return false;
    text.replace(at, from.size(), to);
    return true;
  }

  std::filesystem::path dir_;
  pid_t pid_ = -1;
  bool ok_ = false;
};

/// Handles LCM until `done()` or `seconds` passed (a liveness bound), calling `each` about every
/// 10 ms. Returns done().
inline bool wait_for(LcmBus& lcm, const std::function<bool()>& done, double seconds,
                     const std::function<void()>& each = {}) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < deadline) {
    lcm.handle_timeout(10);
    if (each) each();
    if (done()) return true;
  }
  return done();
}

}  // namespace porter::piper::test
