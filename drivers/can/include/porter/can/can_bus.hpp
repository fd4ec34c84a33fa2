#pragma once
// The CAN bus a driver talks through. One interface, several transports, chosen by a config
// string (see open_can_bus in can_transport.hpp): SocketCAN, serial SLCAN, LCM-carried frames,
// and in-memory buses for unit tests.
//
// Contract for every implementation:
// - send() and receive() never throw; failures come back as a CanStatus, and last_error() says
//   what happened in words a field engineer can act on.
// - receive() waits at most timeout_ms (0 = poll, < 0 = wait forever) and returns ok with a
//   frame, timeout, or a failure status. Frames sent by this endpoint are not received by it.
// - A bus that failed to open reports closed on every call.
//
// Thread-safety: send() may be called from one thread while another thread is inside
// receive() (a driver's control loop sends while its reader thread receives); two threads must
// not call send() (or receive()) on the same bus at once.

#include <string>

#include "porter/can/can_frame.hpp"

namespace porter::can {

enum class CanStatus {
  ok,             ///< frame sent / received
  timeout,        ///< nothing arrived within the timeout
  closed,         ///< the bus is not open (failed to open, or closed)
  invalid_frame,  ///< send(): the frame is not valid() (ID too large, dlc > 8)
  tx_full,        ///< send(): the transport's transmit queue is full; the frame was not sent
  error_frame,    ///< receive(): the controller reported a bus error (the frame holds its details)
  bus_off,        ///< the controller is bus-off; nothing is sent until it recovers
  io_error,       ///< the operating system or adapter reported an error (see last_error())
};

/// Short lower-case name ("ok", "timeout", "bus_off", ...).
const char* to_string(CanStatus status);

class CanBus {
 public:
  virtual ~CanBus() = default;

  virtual CanStatus send(const CanFrame& frame) = 0;
  virtual CanStatus receive(CanFrame& frame, int timeout_ms) = 0;

  /// The config string this bus was opened from ("memory:base", "socketcan:can0", ...).
  virtual std::string describe() const = 0;
  /// The latest failure in words, "" when none happened.
  virtual std::string last_error() const = 0;
  /// True while the bus can send and receive.
  virtual bool is_open() const = 0;
};

}  // namespace porter::can
