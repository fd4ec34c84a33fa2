#pragma once
// Controller error reports (SocketCAN error frames) in words.
//
// A SocketCAN socket with an error filter receives, besides data frames, "error frames": the
// CAN ID carries error-class bits (bus-off, controller state, protocol violation, missing ACK,
// ...) and the 8 data bytes their details (linux/can/error.h, a kernel ABI). SocketCanBus
// returns them from receive() as CanStatus::error_frame (or bus_off) with the frame holding the
// class bits in `id` and the details in `data`; decode_error_frame() turns that into flags and
// a sentence for the log.
//
// Pure and total: any id and any data decode (bytes beyond dlc read as zero); never throws.
// Thread-safety: reentrant.

#include <cstdint>
#include <string>

#include "porter/can/can_frame.hpp"

namespace porter::can {

struct ControllerError {
  std::uint32_t classes = 0;     ///< error-class bits (CAN_ERR_TX_TIMEOUT ... CAN_ERR_CNT)
  bool bus_off = false;          ///< the controller left the bus; nothing is sent until restart
  bool error_passive = false;    ///< rx or tx error counter above 127
  bool warning = false;          ///< rx or tx error counter above 95
  bool back_to_active = false;   ///< recovered to error-active
  bool restarted = false;        ///< the controller was restarted (after bus-off)
  bool no_ack = false;           ///< a transmitted frame got no ACK (no other node on the bus?)
  bool overflow = false;         ///< a controller receive or transmit buffer overflowed
  int tx_error_count = -1;       ///< transmit error counter, -1 when not reported
  int rx_error_count = -1;       ///< receive error counter, -1 when not reported
  std::string text;              ///< e.g. "bus-off; no ACK on transmission"
};

/// Decodes an error frame as SocketCanBus returns it (class bits in frame.id).
ControllerError decode_error_frame(const CanFrame& frame);

}  // namespace porter::can
