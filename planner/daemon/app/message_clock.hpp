#pragma once
// The clock of the messages a process receives, for replays: lcm-logplayer plays a log with its
// recorded stamps, so a map or a state stamped an hour ago is new to the process. MessageClock
// follows the newest stamp it was given (µs) and runs on the monotonic clock between stamps:
// now() = newest stamp + time since it was given. Before the first stamp it is the wall clock.
//
// Thread-safety: observe() and now() may be called from any thread.

#include <atomic>
#include <cstdint>

#include "porter/runtime/clock.hpp"

namespace porter::planner_app {

class MessageClock {
 public:
  /// A message stamped utime was received now.
  void observe(std::int64_t utime) {
    const std::int64_t offset = utime - runtime::mono_ns() / 1000;
    offset_us_.store(offset, std::memory_order_relaxed);
    set_.store(true, std::memory_order_release);
  }
  std::int64_t now() const {
    if (!set_.load(std::memory_order_acquire)) return runtime::wall_utime();
    return runtime::mono_ns() / 1000 + offset_us_.load(std::memory_order_relaxed);
  }

 private:
  std::atomic<std::int64_t> offset_us_{0};
  std::atomic<bool> set_{false};
};

}  // namespace porter::planner_app
