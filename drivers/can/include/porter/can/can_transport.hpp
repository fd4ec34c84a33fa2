#pragma once
// Opens a CAN bus from a config string:
//
//   socketcan:IFACE             Linux SocketCAN interface (can0, vcan0): socketcan_bus.hpp
//   slcan:DEVICE@BITRATE[?baud=N]  serial-line USB-CAN adapter on a tty, CAN bitrate in bit/s
//                               (e.g. slcan:/dev/ttyACM0@500000): slcan_bus.hpp
//   lcm:CHANNEL[@URL]           frames carried as can_frame_t on the registry channel CHANNEL
//                               (CAN_BASE, CAN_ARM) over LCM at URL (default $LCM_DEFAULT_URL),
//                               so lcm-spy and lcm-logger see the raw frames of a simulated run
//   memory:NAME                 in-process bus NAME (unit tests)
//
// Never returns null and never throws: a string that names no transport, or a bus that cannot
// be opened, gives a bus whose is_open() is false and whose last_error() says why, naming the
// string. `node_name` identifies this endpoint where the transport carries it (the LCM bus's
// `sender` field, so an endpoint ignores its own frames).

#include <memory>
#include <string>

#include "porter/can/can_bus.hpp"

namespace porter::can {

std::unique_ptr<CanBus> open_can_bus(const std::string& spec, const std::string& node_name);

/// `spec` with "@url" appended when it is an lcm: spec without a URL and `url` is not empty
/// (a process's configured LCM URL also carries its LCM-carried CAN buses); otherwise `spec`.
std::string with_lcm_url(const std::string& spec, const std::string& url);

/// A bus that failed to open: every call returns closed, last_error() returns `reason`.
std::unique_ptr<CanBus> make_failed_bus(const std::string& spec, const std::string& reason);

}  // namespace porter::can
