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
// Thread-safety: none; one thread drives a node.

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

  /// Device name for logs ("scout_mini", "piper").
  virtual std::string name() const = 0;
};

}  // namespace porter::can
