#pragma once
// What porter-tracker's timed thread exchanges with its two I/O threads, so that it never
// waits for them and never touches the receive side of LCM or the log:
//
//   LCM receive thread ──InputEvent──▶ [SpscRing] ──▶ timed thread ──▶ BASE_CMD, ARM_CMD (sent by
//   (decodes, converts)               (wake, apply_input, Tracker::step)   it, on its own LCM
//                                                     │                    instance)
//                                                     └──CycleReport──▶ [SpscRing] ──▶ publisher
//                                                        thread: TRACKER_STATUS, HEARTBEAT, log
//
// SpscRing is a fixed ring of preallocated slots for one producer thread and one consumer
// thread: no lock, no allocation by the ring itself, neither side ever waits for the other.
// A full ring refuses the new element (the producer decides: the receive thread retries, the
// timed thread counts a lost report).
//
// apply_input() feeds the events to the Tracker in arrival order, exactly as handling them one
// by one in LCM callbacks did, and says in LogLines what the process logs about them.
//
// Thread-safety: SpscRing as above; everything else reentrant. Failure: nothing throws except
// the SpscRing constructor (std::invalid_argument for capacity 0).

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "porter/runtime/heartbeat.hpp"
#include "porter/runtime/log.hpp"
#include "porter/tracker/tracker.hpp"
#include "tracker_messages.hpp"

namespace porter::tracker_app {

template <class T>
class SpscRing {
 public:
  explicit SpscRing(std::size_t capacity) : slots_(capacity) {
    if (capacity == 0) throw std::invalid_argument("SpscRing: capacity must be positive");
  }
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  std::size_t capacity() const { return slots_.size(); }

  /// Producer: the free slot to fill (it holds whatever it held before), or nullptr when full.
  T* slot_to_fill() {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= slots_.size()) return nullptr;
    return &slots_[head % slots_.size()];
  }
  /// Producer: hands the slot returned by slot_to_fill() to the consumer.
  void push_filled() { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

  /// Consumer: the oldest filled slot, or nullptr when empty. It stays the consumer's until
  /// pop() (the producer does not write it).
  T* front() {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return nullptr;
    return &slots_[tail % slots_.size()];
  }
  /// Consumer: releases the slot returned by front() for reuse.
  void pop() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

 private:
  std::vector<T> slots_;
  alignas(64) std::atomic<std::uint64_t> head_{0};  // written by the producer
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
};

/// A ROBOT_STATE that converted.
struct StateInput {
  tracker::MeasuredState state;
  std::int64_t receive_utime = 0;
};
/// A TRAJECTORY that converted.
struct TrajectoryInput {
  tracker::TrajectoryOffer offer;
  std::int64_t receive_utime = 0;
};
/// A TRAJECTORY that did not convert.
struct InvalidTrajectoryInput {
  std::int64_t plan_id = 0;
  std::string error;
};
/// An ESTOP message.
struct EstopInput {
  bool active = false;
  std::string source;
  std::string reason;
  std::int64_t receive_utime = 0;
};
using InputEvent = std::variant<std::monostate, StateInput, TrajectoryInput,
                                InvalidTrajectoryInput, EstopInput>;

struct LogLine {
  runtime::LogLevel level = runtime::LogLevel::info;
  std::string text;
};

/// Feeds one event to `tracker` (std::monostate: nothing) and appends to `log` what the process
/// logs about it: a trajectory accepted or refused, the e-stop engaged or released.
void apply_input(tracker::Tracker& tracker, InputEvent& event, std::vector<LogLine>& log);

/// What the publisher thread sends for one period, filled by the timed thread (only for the
/// periods with something to send: a status, log lines, a health change, or a heartbeat due).
struct CycleReport {
  std::int64_t utime = 0;                  ///< the step's time (stamp of TRACKER_STATUS)
  bool send_status = false;
  tracker::TrackerOutput out;              ///< the step's output (copied when send_status)
  std::string last_refusal;                ///< for TRACKER_STATUS (copied when send_status)
  LoopFigures figures;                     ///< for TRACKER_STATUS (set when send_status)
  tracker::TrackerState state = tracker::TrackerState::idle;
  runtime::HeartbeatHealth health = runtime::HeartbeatHealth::ok;
  double loop_rate_hz = 0.0;
  std::int64_t overruns = 0;
  std::vector<LogLine> log;                ///< lines to write, in order
};

/// The state-change log line for `out` (TRACKING, FINISHED, IDLE at info, the rest warn).
LogLine state_change_line(const tracker::TrackerOutput& out);

}  // namespace porter::tracker_app
