#pragma once
// A fixed-rate loop on absolute deadlines, with its own timing statistics.
//
//   PeriodicLoop loop(0.01);                 // 100 Hz
//   while (!stop_requested()) {
//     loop.wait();                           // sleeps until the next deadline (absolute time)
//     step();
//   }
//   loop.stats().lateness_quantile_s(0.99);  // wake-up jitter
//
// Deadlines are k * period after the first wait(), on CLOCK_MONOTONIC, slept with
// clock_nanosleep(TIMER_ABSTIME), so a late wake-up does not shift the later deadlines (no
// drift). When a step runs past one or more whole deadlines, the missed deadlines are counted
// as overruns and skipped: the loop resumes at the next future deadline instead of running a
// burst of catch-up steps.
//
// Thread-safety: one thread drives the loop; stats() returns a copy and may be called from that
// thread only.

#include <cstdint>
#include <vector>

namespace porter::runtime {

/// Wake-up lateness statistics (how long after its deadline each wait() returned).
class LatenessStats {
 public:
  /// Histogram resolution 1 µs up to `histogram_range_s`; later wake-ups fall in the last bin
  /// (their exact value still counts in max_s()).
  explicit LatenessStats(double histogram_range_s = 0.05);

  void add(double lateness_s);
  void reset();

  std::uint64_t count() const { return count_; }
  double max_s() const { return max_s_; }
  double mean_s() const { return count_ ? sum_s_ / static_cast<double>(count_) : 0.0; }
  /// q in [0, 1]; 0 when empty. Resolution 1 µs.
  double quantile_s(double q) const;

 private:
  std::vector<std::uint32_t> bins_;
  std::uint64_t count_ = 0;
  double sum_s_ = 0.0;
  double max_s_ = 0.0;
};

class PeriodicLoop {
 public:
  /// period_s > 0.
  explicit PeriodicLoop(double period_s);

  /// Sleeps until the next deadline and returns how late the wake-up was, s (>= 0).
  double wait();

  double period_s() const { return period_s_; }
  /// Completed wait() calls.
  std::uint64_t cycles() const { return cycles_; }
  /// Deadlines skipped because a step ran past them.
  std::uint64_t overruns() const { return overruns_; }
  /// Measured rate over the last second of cycles, Hz (0 before one second has passed).
  double measured_rate_hz() const { return rate_hz_; }
  const LatenessStats& lateness() const { return lateness_; }
  /// Forgets statistics (not the deadline schedule).
  void reset_stats();

 private:
  double period_s_;
  std::int64_t period_ns_;
  std::int64_t next_ns_ = 0;
  std::uint64_t cycles_ = 0;
  std::uint64_t overruns_ = 0;
  LatenessStats lateness_;
  std::int64_t rate_window_start_ns_ = 0;
  std::uint64_t rate_window_cycles_ = 0;
  double rate_hz_ = 0.0;
};

}  // namespace porter::runtime
