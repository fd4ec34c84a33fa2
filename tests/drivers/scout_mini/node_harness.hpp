#pragma once
// porter-base's real loop (BaseNode) and a simulated Scout Mini (the Simulator library hosting
// ScoutMiniFirmware, stepped in real time on its own thread), joined by a CAN bus given as a
// spec (memory:NAME or lcm:CAN_BASE@URL). A client LcmBus on the same URL publishes BASE_CMD and
// ESTOP and reads BASE_STATE. Used by the in-process tests and the porter-base benchmark.

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "base_node.hpp"
#include "porter/can/can_transport.hpp"
#include "porter/channels.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/clock.hpp"
#include "porter/scout_mini/firmware.hpp"
#include "porter/sim/simulator.hpp"

namespace porter::scout_mini::test {

/// A driver config like the shipped one, without reading files.
inline BaseNodeConfig node_config(const std::string& can_spec) {
  BaseNodeConfig c;
  c.can_bus = can_spec;
  c.driver = DriverParams{};
  c.stats_period_s = 3600;
  return c;
}

/// The simulated base, stepped every millisecond on a thread.
class SimulatedBase {
 public:
  explicit SimulatedBase(const std::string& can_spec)
      : endpoint_(can::open_can_bus(can_spec, "porter-sim")),
        sim_(sim::World(Scene{}, RobotModel{})) {
    sim_.add_bus("base", endpoint_->is_open() ? endpoint_.get() : nullptr);
    firmware_ = static_cast<ScoutMiniFirmware*>(
        sim_.add_node("base", std::make_unique<ScoutMiniFirmware>()));
    const ScoutMiniFirmware* fw = firmware_;
    sim_.set_base_source(std::make_unique<sim::FunctionBaseSource>([fw] {
      sim::BaseTruth truth;
      truth.pose_W = {fw->pose().x_m, fw->pose().y_m, fw->pose().yaw_rad};
      truth.v_mps = fw->v_mps();
      truth.omega_radps = fw->omega_radps();
      return truth;
    }));
    sim_.world().set_utime_origin(runtime::wall_utime());
    thread_ = std::thread([this] {
      const double t0 = runtime::mono_s();
      while (!stop_.load()) {
        {
          std::lock_guard<std::mutex> lock(mutex_);
          sim_.step_to(runtime::mono_s() - t0);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  }
  ~SimulatedBase() {
    stop_ = true;
    thread_.join();
  }
  bool open() const { return endpoint_->is_open(); }
  std::string error() const { return endpoint_->last_error(); }
  /// Runs fn with the simulator paused (faults, reading the firmware).
  void with(const std::function<void(sim::Simulator&, ScoutMiniFirmware&)>& fn) {
    std::lock_guard<std::mutex> lock(mutex_);
    fn(sim_, *firmware_);
  }
  /// Called (on the simulation thread) with every frame on the bus.
  void tap(sim::Simulator::FrameTap tap) {
    std::lock_guard<std::mutex> lock(mutex_);
    sim_.set_frame_tap(std::move(tap));
  }

 private:
  std::unique_ptr<can::CanBus> endpoint_;
  sim::Simulator sim_;
  ScoutMiniFirmware* firmware_ = nullptr;
  std::mutex mutex_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// porter-base's loop on a thread.
class DriverProcess {
 public:
  DriverProcess(const BaseNodeConfig& config, const std::string& lcm_url)
      : DriverProcess(config, lcm_url, can::open_can_bus(config.can_bus, "porter-base")) {}
  /// With a bus the caller opened (and may cut, e.g. MemoryBus::disconnect()).
  DriverProcess(const BaseNodeConfig& config, const std::string& lcm_url,
                std::unique_ptr<can::CanBus> bus)
      : lcm_(lcm_url), node_(config, std::move(bus), lcm_) {
    thread_ = std::thread([this] { exit_code_ = node_.run([this] { return stop_.load(); }); });
  }
  ~DriverProcess() { stop(); }
  int stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    return exit_code_;
  }
  const BaseNode& node() const { return node_; }

 private:
  LcmBus lcm_;
  BaseNode node_;
  std::atomic<bool> stop_{false};
  std::atomic<int> exit_code_{-1};
  std::thread thread_;
};

/// The tracker's and the operator's side: BASE_CMD, ESTOP out; BASE_STATE in.
class Client {
 public:
  explicit Client(const std::string& lcm_url) : lcm_(lcm_url) {
    lcm_.subscribe(channels::kBaseState, [this](const porter::base_state_t& s) {
      std::lock_guard<std::mutex> lock(mutex_);
      state_ = s;
      ++states_;
      if (on_state_) on_state_(s);
    });
    thread_ = std::thread([this] {
      while (!stop_.load()) lcm_.handle_timeout(20);
    });
  }
  ~Client() {
    stop_ = true;
    thread_.join();
  }
  void command(double v, double w, bool enabled = true) {
    porter::base_cmd_t c;
    c.utime = runtime::wall_utime();
    c.enabled = enabled;
    c.v_mps = v;
    c.omega_radps = w;
    c.plan_id = -1;
    c.source = "test";
    lcm_.publish(channels::kBaseCmd, c);
  }
  void estop(bool active) {
    porter::estop_t e;
    e.utime = runtime::wall_utime();
    e.active = active;
    e.source = "test";
    e.reason = active ? "stop" : "clear";
    lcm_.publish(channels::kEstop, e);
  }
  porter::base_state_t state() {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
  }
  long states() {
    std::lock_guard<std::mutex> lock(mutex_);
    return states_;
  }
  void on_state(std::function<void(const porter::base_state_t&)> fn) {
    std::lock_guard<std::mutex> lock(mutex_);
    on_state_ = std::move(fn);
  }
  /// Streams (v, w) at 100 Hz for `seconds`, then returns.
  void stream(double v, double w, double seconds) {
    const double end = runtime::mono_s() + seconds;
    while (runtime::mono_s() < end) {
      command(v, w);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  /// Waits until pred(BASE_STATE) holds or the timeout passes.
  bool wait_for(const std::function<bool(const porter::base_state_t&)>& pred, double timeout_s) {
    const double end = runtime::mono_s() + timeout_s;
    while (runtime::mono_s() < end) {
      if (states() > 0 && pred(state())) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

 private:
  LcmBus lcm_;
  std::mutex mutex_;
  porter::base_state_t state_;
  long states_ = 0;
  std::function<void(const porter::base_state_t&)> on_state_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace porter::scout_mini::test
