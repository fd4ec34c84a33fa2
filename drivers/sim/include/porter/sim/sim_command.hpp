#pragma once
// Faults and world changes on demand: what a test asks of the simulator, as a library value
// (Simulator::apply) or over LCM (sim_command_t on SIM_COMMAND, converted by porter-sim).
//
//   kind              target           fields used
//   drop_bus          bus name         -             frames stop crossing the bus both ways
//   restore_bus       bus name         -
//   stop_stream       device name      can_id        the device stops sending that frame
//   resume_stream     device name      can_id
//   raise_error       device name      error_code    device error bits (Scout Mini: 0x211 word)
//   clear_errors      device name      -
//   power_cycle       device name      duration_s    off for duration_s, then boots
//   add_box           obstacle name    center_W, size_m, yaw_rad   a box in W appears
//   remove_obstacle   obstacle name    -             any obstacle (scene or added) disappears
//
// Thread-safety: a value type.

#include <cstdint>
#include <string>

#include <Eigen/Core>

namespace porter::sim {

struct SimCommand {
  enum class Kind {
    drop_bus,
    restore_bus,
    stop_stream,
    resume_stream,
    raise_error,
    clear_errors,
    power_cycle,
    add_box,
    remove_obstacle,
  };
  Kind kind = Kind::drop_bus;
  std::string target;
  std::uint32_t can_id = 0;
  std::uint32_t error_code = 0;
  double duration_s = 0.0;
  Eigen::Vector3d center_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

const char* to_string(SimCommand::Kind kind);

/// The outcome of a command: ok, or why it was refused (unknown bus or device, unsupported
/// fault, invalid box, ...).
struct SimResult {
  bool ok = false;
  std::string message;
};

}  // namespace porter::sim
