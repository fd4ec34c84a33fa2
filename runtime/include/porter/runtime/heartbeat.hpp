#pragma once
// The HEARTBEAT every Porter process publishes at 1 Hz (process_heartbeat_t).
//
//   Heartbeat heartbeat(bus, "porter-base");
//   ... in the main loop:
//   heartbeat.update(HeartbeatHealth::ok, "", loop.measured_rate_hz(), loop.overruns());
//
// update() publishes only when a second has passed since the last heartbeat (or immediately
// when the health changed), so it may be called every loop cycle. Each heartbeat carries the
// datagrams the process's LCM guard dropped (LcmBus::process_decode_failures()).
//
// Thread-safety: one thread calls update(); LcmBus::publish is thread-safe.

#include <cstdint>
#include <string>

#include "porter/lcm_bus.hpp"

namespace porter::runtime {

enum class HeartbeatHealth : std::int8_t { ok = 0, warn = 1, error = 2 };

class Heartbeat {
 public:
  Heartbeat(LcmBus& bus, std::string process, double period_s = 1.0);

  /// Publishes when due or when `health` differs from the last published health. Returns true
  /// when a message was published.
  bool update(HeartbeatHealth health, const std::string& status, double loop_rate_hz = 0.0,
              std::int64_t loop_overruns = 0);

  std::uint64_t published() const { return published_; }

 private:
  LcmBus& bus_;
  std::string process_;
  std::string host_;
  std::int64_t start_utime_;
  std::int64_t period_ns_;
  std::int64_t last_ns_ = 0;
  bool first_ = true;
  HeartbeatHealth last_health_ = HeartbeatHealth::ok;
  std::uint64_t published_ = 0;
};

}  // namespace porter::runtime
