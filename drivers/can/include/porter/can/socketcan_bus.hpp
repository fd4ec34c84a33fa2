#pragma once
// A CAN bus on a Linux SocketCAN interface (`socketcan:can0`, `socketcan:vcan0`): one raw CAN
// socket bound to the interface.
//
// - Received frames carry the kernel's receive timestamp (SO_TIMESTAMP, µs since the epoch).
// - Error frames are enabled (all classes): receive() returns CanStatus::error_frame, or
//   CanStatus::bus_off for a bus-off report, with the frame holding the error (decode it with
//   decode_error_frame(), can_error.hpp); last_error() holds its text.
// - send() on a full transmit queue returns tx_full (ENOBUFS / EAGAIN), on an interface that is
//   down io_error with the reason.
// - The interface's link (bitrate, up/down, restart-ms) is set up outside Porter, e.g.
//   `ip link set can0 up type can bitrate 500000 restart-ms 100`.
//
// Opening fails (is_open() false, last_error() says why, naming the interface) when the kernel
// has no SocketCAN support (socket(PF_CAN) is refused: the message names the missing kernel
// support and the modules to load), when the interface does not exist, or when binding fails.
//
// Thread-safety: per the CanBus contract (one sending thread, one receiving thread).

#include <memory>
#include <mutex>
#include <string>

#include "porter/can/can_bus.hpp"

namespace porter::can {

class SocketCanBus final : public CanBus {
 public:
  /// Opens a raw socket on `interface_name`. Never null; check is_open() / last_error().
  static std::unique_ptr<SocketCanBus> open(const std::string& interface_name);
  ~SocketCanBus() override;

  CanStatus send(const CanFrame& frame) override;
  CanStatus receive(CanFrame& frame, int timeout_ms) override;
  std::string describe() const override { return "socketcan:" + interface_; }
  std::string last_error() const override;
  bool is_open() const override { return fd_ >= 0; }

 private:
  explicit SocketCanBus(std::string interface_name) : interface_(std::move(interface_name)) {}
  void set_error(std::string error);

  std::string interface_;
  int fd_ = -1;
  mutable std::mutex error_mutex_;
  std::string error_;
};

/// Whether this kernel lets a process open a CAN socket. False with `reason` filled (the errno
/// text and what to do) when socket(PF_CAN, SOCK_RAW, CAN_RAW) is refused.
bool socketcan_supported(std::string& reason);

}  // namespace porter::can
