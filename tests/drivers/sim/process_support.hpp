#pragma once
// Multi-process tests of porter-sim: a child process (stderr in a log file, stopped by PID with
// SIGTERM, killed by PID if it outlives the test) and config files derived from the shipped ones
// with absolute paths and the test's private LCM URL and UDP ports.

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"

extern char** environ;

namespace porter::sim::test {

inline const std::string kSource = PORTER_SOURCE_DIR;

class Child {
 public:
  Child(const std::string& exe, std::vector<std::string> args, const std::string& log)
      : log_(log) {
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (posix_spawn(&pid_, exe.c_str(), &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  pid_t pid() const { return pid_; }
  /// SIGTERM, then the exit status (-1 when it did not exit within the timeout).
  int stop(double timeout_s = 10.0) {
    if (pid_ <= 0) return -1;
    ::kill(pid_, SIGTERM);
    const double end = runtime::mono_s() + timeout_s;
    int status = 0;
    while (runtime::mono_s() < end) {
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }
  std::string log() const {
    std::ifstream in(log_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  pid_t pid_ = -1;
  std::string log_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// This test run's directory for config files (per PID), removed when the program ends.
struct TempDir {
  TempDir()
      : path(std::filesystem::temp_directory_path() /
             ("porter_sim_process_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::filesystem::path path;
};

/// Writes `text` to a file of this test run and returns its path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  static TempDir dir;
  const std::string path = (dir.path / name).string();
  std::ofstream(path) << text;
  return path;
}

/// The shipped config/drivers/<file> with its relative paths made absolute.
inline std::string shipped_config(const std::string& file) {
  return std::regex_replace(read_text(kSource + "/config/drivers/" + file), std::regex(R"(\.\./)"),
                            kSource + "/config/");
}

/// porter-sim's shipped config with the LiDAR sending to the given loopback ports (0 = LiDAR
/// off): UDP, like udpm, is host-wide, so a test never uses the default 56301 / 56401.
inline std::string sim_config_file(const std::string& name, int point_port, int imu_port) {
  std::string text = shipped_config("porter_sim.yaml");
  if (point_port == 0) {
    text = std::regex_replace(text, std::regex("\n  enabled: true"), "\n  enabled: false");
  } else {
    text = std::regex_replace(text, std::regex("point_port: 56301"),
                              "point_port: " + std::to_string(point_port));
    text = std::regex_replace(text, std::regex("imu_port: 56401"),
                              "imu_port: " + std::to_string(imu_port));
  }
  text = std::regex_replace(text, std::regex("point_source_port: 56300"), "point_source_port: 0");
  text = std::regex_replace(text, std::regex("imu_source_port: 56400"), "imu_source_port: 0");
  return write_temp(name, text);
}

/// A box for SIM_COMMAND ADD_BOX: centre and size in the world frame, metres.
struct SimBox {
  double x = 0, y = 0, z = 0;
  double size_x = 0.5, size_y = 0.5, size_z = 0.5;
};

/// What the observing side of a multi-process test shares: an LCM bus handled on its own thread,
/// a mutex `m` over what the subscription handlers store, a polling wait on a predicate under that
/// mutex, and the commands a test sends to the simulator and the drivers. A derived observer
/// subscribes in its constructor body, then calls listen(); its destructor calls stop_listening()
/// first, so no handler runs while its members are being destroyed.
class BusObserver {
 public:
  BusObserver(const std::string& url, std::string source) : lcm(url), source_(std::move(source)) {}
  BusObserver(const BusObserver&) = delete;
  BusObserver& operator=(const BusObserver&) = delete;
  ~BusObserver() { stop_listening(); }

  /// Polls `pred` under the mutex every 10 ms until it holds or the timeout passes, calling
  /// `each` (outside the mutex) before every poll; the last poll is made after the timeout.
  bool wait_for(const std::function<bool()>& pred, double timeout_s,
                const std::function<void()>& each = {}) {
    const double end = runtime::mono_s() + timeout_s;
    while (runtime::mono_s() < end) {
      if (each) each();
      {
        std::lock_guard<std::mutex> l(m);
        if (pred()) return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::lock_guard<std::mutex> l(m);
    return pred();
  }

  void base_cmd(double v, double w) {
    porter::base_cmd_t c;
    c.utime = runtime::wall_utime();
    c.enabled = true;
    c.v_mps = v;
    c.omega_radps = w;
    c.plan_id = -1;
    c.source = source_;
    lcm.publish(channels::kBaseCmd, c);
  }

  void sim_command(std::int8_t kind, const std::string& target, double duration_s = 0,
                   const SimBox& box = {}) {
    porter::sim_command_t c;
    c.utime = runtime::wall_utime();
    c.command_id = ++command_id_;
    c.command = kind;
    c.target = target;
    c.duration_s = duration_s;
    // LCM's C++ types leave numeric fields uninitialised: every field is set.
    c.can_id = 0;
    c.error_code = 0;
    c.yaw_rad = 0.0;
    c.center_x_m = box.x;
    c.center_y_m = box.y;
    c.center_z_m = box.z;
    c.size_x_m = box.size_x;
    c.size_y_m = box.size_y;
    c.size_z_m = box.size_z;
    c.source = source_;
    lcm.publish(channels::kSimCommand, c);
  }

  LcmBus lcm;
  std::mutex m;

 protected:
  void listen() {
    thread_ = std::thread([this] {
      while (!stop_.load()) lcm.handle_timeout(20);
    });
  }
  void stop_listening() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::string source_;
  std::int64_t command_id_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace porter::sim::test
