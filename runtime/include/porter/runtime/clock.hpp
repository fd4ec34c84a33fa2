#pragma once
// Clocks for Porter processes.
//
// utime (LCM's convention) is wall-clock time in microseconds since the Unix epoch; it stamps
// messages so logs from several hosts line up. Intervals, timeouts and staleness are measured on
// the monotonic clock, which never jumps when NTP or PTP adjusts the wall clock.
//
// Thread-safety: all functions are reentrant.

#include <cstdint>
#include <ctime>

namespace porter::runtime {

/// Wall-clock time, µs since the Unix epoch (CLOCK_REALTIME).
inline std::int64_t wall_utime() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000 + ts.tv_nsec / 1000;
}

/// Monotonic time, ns since an arbitrary fixed point (CLOCK_MONOTONIC).
inline std::int64_t mono_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

/// Monotonic time in seconds (for arithmetic on durations).
inline double mono_s() { return static_cast<double>(mono_ns()) * 1e-9; }

}  // namespace porter::runtime
