#pragma once
// A simulated device on a CAN bus (firmware model): the interface porter-sim hosts and tests
// drive directly. The model never reads a clock; the caller passes simulated time, so a test or
// a faster-than-real-time simulator steps it at any speed.
//
//   node.receive(frame, t_s);          // a frame from the bus reaches the device at time t_s
//   node.advance(t_s, out);            // physics up to t_s; frames the device sends up to t_s
//                                      // are appended to `out` (stamped with their send time)
//
// Time never goes backwards between calls. advance() may be called at any rate; a model sends
// its periodic frames at their own rates (e.g. 50 Hz) whatever the call rate, so a caller that
// advances every millisecond and one that advances every 20 ms see the same frames.
//
// Frame timestamps: frames appended by advance() carry utime = round(send time in s * 1e6), i.e.
// microseconds of simulated time; the host (porter-sim) maps them to wall-clock time.
//
// Faults on demand: the four fault hooks below let a simulator (and tests) break a device the
// way hardware breaks. A model that does not support a hook keeps the default, which does
// nothing and returns false.
//
// Thread-safety: none; one thread drives a node.

#include <cstdint>
#include <string>
#include <vector>

#include "porter/can/can_frame.hpp"

namespace porter::can {

class SimulatedNode {
 public:
  virtual ~SimulatedNode() = default;

  /// A frame on the bus reached this device at simulated time t_s (seconds).
  virtual void receive(const CanFrame& frame, double t_s) = 0;

  /// Advances the device's state to t_s and appends the frames it transmits in (last, t_s].
  virtual void advance(double t_s, std::vector<CanFrame>& out) = 0;

  /// Device name for logs and fault commands ("scout_mini", "piper").
  virtual std::string name() const = 0;

  // ---- fault hooks (true when the model supports the fault and applied it) --------------------

  /// Power is cut at t_s for off_s seconds: the device sends nothing and ignores the bus, then
  /// boots into its power-on state (as hardware does: mode, counters and errors reset).
  virtual bool power_cycle(double t_s, double off_s) { return false; }
  /// Stops (enabled = false) or resumes one periodic frame stream, by CAN ID.
  virtual bool set_stream_enabled(std::uint32_t can_id, bool enabled) { return false; }
  /// Raises device error bits (the device's own error word, e.g. the Scout Mini's 0x211 error
  /// code); the device reacts as its firmware would (reports them, stops if they are faults).
  virtual bool raise_error(std::uint32_t code) { return false; }
  /// Clears every raised error.
  virtual bool clear_errors() { return false; }
};

}  // namespace porter::can
