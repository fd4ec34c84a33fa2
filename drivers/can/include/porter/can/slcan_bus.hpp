#pragma once
// A CAN bus through a serial-line (SLCAN / LAWICEL) USB-CAN adapter on a tty, e.g.
// `slcan:/dev/ttyACM0@500000` (see slcan_protocol.hpp for the protocol).
//
// Opening: the tty is put in raw mode (8N1, no flow control, at `serial_baud`; USB CDC adapters
// ignore the baud), then the channel is closed (C, in case it was left open), the bitrate is set
// (Sn) and the channel opened (O), each command waiting up to `reply_timeout_ms` for the
// adapter's reply. A refused command (BEL), a missing reply or a tty error makes open() return
// a bus whose is_open() is false and whose last_error() names the device and the command.
// Closing (destructor) sends C.
//
// Running: send() writes one frame line; the adapter's replies to it ('z', CR, or BEL) arrive on
// the receive side. receive() returns frames with utime = host receive time; a BEL from the
// adapter (a frame it could not queue) makes that receive() call return io_error with
// last_error() saying so (the next call continues); a malformed line is counted and skipped. A
// hang-up (the adapter unplugged) closes the bus: every later call returns closed.
//
// Thread-safety: per the CanBus contract (one sending thread, one receiving thread).

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>

#include "porter/can/can_bus.hpp"
#include "porter/can/slcan_protocol.hpp"

namespace porter::can {

struct SlcanOptions {
  std::string device;                 ///< tty path, e.g. /dev/ttyACM0
  std::uint32_t bitrate = 500000;     ///< CAN bitrate, bit/s (must have an Sn code)
  std::uint32_t serial_baud = 115200; ///< tty baud (UART adapters; USB CDC ignores it)
  int reply_timeout_ms = 500;         ///< wait for each open/close command's reply
};

class SlcanBus final : public CanBus {
 public:
  /// Opens and configures the adapter. Never null; check is_open() / last_error().
  static std::unique_ptr<SlcanBus> open(const SlcanOptions& options, std::string describe);
  ~SlcanBus() override;

  CanStatus send(const CanFrame& frame) override;
  CanStatus receive(CanFrame& frame, int timeout_ms) override;
  std::string describe() const override { return describe_; }
  std::string last_error() const override;
  bool is_open() const override { return fd_ >= 0 && !hung_up_.load(); }

  /// Commands the adapter refused (BEL) since open.
  std::uint64_t refused() const { return refused_.load(); }
  /// Adapter lines that were not valid replies, skipped.
  std::uint64_t malformed() const { return malformed_.load(); }

 private:
  SlcanBus(SlcanOptions options, std::string describe);
  bool configure_tty();
  bool command(const std::string& cmd, const char* what);
  bool write_all(const std::string& bytes, int timeout_ms);
  void set_error(std::string error);

  SlcanOptions options_;
  std::string describe_;
  int fd_ = -1;
  slcan::SlcanDecoder decoder_;
  std::deque<CanFrame> frames_;
  std::atomic<bool> hung_up_{false};
  std::atomic<std::uint64_t> refused_{0};
  std::atomic<std::uint64_t> malformed_{0};
  mutable std::mutex error_mutex_;
  std::string error_;
};

/// Parses "DEVICE@BITRATE[?baud=N]" (the part after `slcan:`). False with `error` set when the
/// text does not have that form or the bitrate has no SLCAN code.
bool parse_slcan_target(const std::string& target, SlcanOptions& options, std::string& error);

}  // namespace porter::can
