#include "porter/can/can_bus.hpp"

namespace porter::can {

const char* to_string(CanStatus status) {
  switch (status) {
    case CanStatus::ok: return "ok";
    case CanStatus::timeout: return "timeout";
    case CanStatus::closed: return "closed";
    case CanStatus::invalid_frame: return "invalid_frame";
    case CanStatus::tx_full: return "tx_full";
    case CanStatus::error_frame: return "error_frame";
    case CanStatus::bus_off: return "bus_off";
    case CanStatus::io_error: return "io_error";
  }
  return "unknown";
}

}  // namespace porter::can
