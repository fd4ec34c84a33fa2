#pragma once
// porter-base's loop: the driver's logic (BaseDriver) wired to a CAN bus and to LCM.
//
// - A receive thread reads the bus and hands every frame to the driver with its monotonic
//   receive time; controller errors and transport errors are logged (rate-limited), a closed bus
//   ends the run.
// - An LCM thread dispatches BASE_CMD and ESTOP as they arrive, so a command's age is measured
//   from its arrival, not from the next tick.
// - The main loop runs at the command rate on absolute deadlines (runtime::PeriodicLoop), at
//   SCHED_FIFO priority when realtime_priority > 0: it ticks the driver and sends its frames
//   (0x421 when due, 0x111), logs the driver's events, publishes BASE_STATE and the HEARTBEAT,
//   and logs a timing line every stats_period_s.
// - Shutdown (stop() true): a zero 0x111 is sent, the receive thread joined.
// Peers restarting (porter-sim, the tracker) need nothing: commands go stale, feedback comes
// back, and the driver re-enters command mode when the base reports standby.
//
// Thread-safety: run() from one thread; the driver is shared with the receive and LCM threads
// under a mutex. `lcm` is handled on the LCM thread only while run() runs (publish is
// thread-safe).

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "base_config.hpp"
#include "porter/can/can_bus.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/runtime/periodic.hpp"
#include "porter/scout_mini/base_driver.hpp"

namespace porter::scout_mini {

class BaseNode {
 public:
  /// `bus` should be open (run() returns 1 at once otherwise).
  BaseNode(const BaseNodeConfig& config, std::unique_ptr<can::CanBus> bus, LcmBus& lcm);
  ~BaseNode();
  BaseNode(const BaseNode&) = delete;
  BaseNode& operator=(const BaseNode&) = delete;

  /// Runs until stop() returns true (checked every cycle). 0 after a clean shutdown, 1 when the
  /// CAN bus closed (adapter gone: the caller should exit so a supervisor restarts it).
  int run(const std::function<bool()>& stop);

  /// Wake-up lateness of the command loop (valid after run()).
  const runtime::LatenessStats& lateness() const { return lateness_; }
  std::uint64_t cycles() const { return cycles_; }

 private:
  void receive_loop();
  void lcm_loop();

  BaseNodeConfig config_;
  std::unique_ptr<can::CanBus> bus_;
  LcmBus& lcm_;
  std::mutex mutex_;
  BaseDriver driver_;
  std::thread rx_thread_;
  std::thread lcm_thread_;
  std::atomic<bool> rx_stop_{false};
  std::atomic<bool> bus_closed_{false};
  runtime::LatenessStats lateness_;
  std::uint64_t cycles_ = 0;
};

}  // namespace porter::scout_mini
