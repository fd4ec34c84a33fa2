#pragma once
// Timing of porter-tracker's control loop, as the process measures it: the period between
// consecutive wake-ups (its deviation from the nominal period is the period jitter), the
// wake-up lateness (PeriodicLoop's own statistics), the work time of a cycle, and the command
// latency (from a period's wake-up until its BASE_CMD and ARM_CMD were handed to the kernel).
// Also the scheduling set-up of the process's threads.
//
// Thread-safety: LoopTiming, one thread (the loop's); the free functions act on the calling
// thread. Failure: nothing throws.

#include <cstdint>
#include <string>

#include "porter/runtime/periodic.hpp"

namespace porter::tracker_app {

class LoopTiming {
 public:
  explicit LoopTiming(double nominal_period_s);

  /// Call right after each wake-up with the monotonic time, ns.
  void on_wake(std::int64_t mono_ns);
  /// Call at the end of each cycle's work with the monotonic time, ns.
  void on_work_done(std::int64_t mono_ns);

  double last_period_s() const { return last_period_s_; }
  /// |period - nominal| statistics (the first wake-up has no period and is not counted).
  const runtime::LatenessStats& period_jitter() const { return jitter_; }
  const runtime::LatenessStats& work() const { return work_; }
  std::uint64_t periods() const { return jitter_.count(); }

 private:
  double nominal_s_;
  std::int64_t last_wake_ns_ = 0;
  double last_period_s_ = 0.0;
  runtime::LatenessStats jitter_;
  runtime::LatenessStats work_;
};

/// One log line: "period jitter p50 12 us p99 80 us max 1.21 ms over 6000 periods; wake-up
/// lateness p50 ... ; work p50 ... ; overruns N".
std::string describe(const LoopTiming& timing, const runtime::PeriodicLoop& loop);

/// "command latency p50 ... p99 ... max ... over N periods".
std::string describe_command_latency(const runtime::LatenessStats& command_latency);

/// The same figures as a JSON object (written by --stats-out for the benchmark).
std::string to_json(const LoopTiming& timing, const runtime::PeriodicLoop& loop,
                    const runtime::LatenessStats& command_latency, double duration_s,
                    bool sched_fifo);

/// Switches the calling thread to SCHED_FIFO at `priority` and locks memory. Returns "" on
/// success, else why not (e.g. "sched_setscheduler: Operation not permitted").
std::string enable_sched_fifo(int priority);

/// SCHED_FIFO priority of the I/O threads (LCM receive, publisher): one below the timed
/// thread's, at least 1.
int io_priority(int timed_priority);

/// Switches the calling thread to SCHED_FIFO at `priority`. Returns "" or why not.
std::string set_thread_fifo(int priority);

/// For the timed thread, before its loop: timer slack 1 ns (a SCHED_OTHER thread's sleeps
/// otherwise end up to 50 µs late; SCHED_FIFO threads have none) and 256 KiB of stack touched,
/// so that with memory locked the loop takes no page fault on its stack.
void prepare_timed_thread();

}  // namespace porter::tracker_app
