#pragma once
// porter-sim's body: builds the simulation from its config and runs it in real time over LCM.
//
// Building: the scene (core's scene loader, with the config's seed), the robot (robot config)
// with the payload attached, one CAN endpoint per bus (open_can_bus, node name "porter-sim";
// lcm: buses without a URL use the config's lcm_url), the devices of each bus (sim_devices.hpp),
// the ground-truth sources (the devices that move the robot; fixed values otherwise), and the
// sensors: SIM_TRUTH at truth_rate_hz, LIO_POSE at lio.rate_hz with its noise, and, when the
// config's lidar is enabled, the simulated MID-360 (porter/sim/lidar_sensor.hpp) whose packets
// go out over UDP to the configured address and ports as the simulation steps (so at the real
// packet rate in real time). More sensors are added with simulator().add_sensor() before run().
//
// Running: every step_s on absolute deadlines, LCM is dispatched (SIM_COMMAND is applied at once
// and its outcome logged) and the simulation is stepped to the monotonic time since start, so
// simulated time follows wall time (real-time factor 1) whatever an individual step costs; a
// status line every status_period_s gives the simulated / wall time ratio, the process's CPU
// time as a share of one core, the share of wall time spent stepping (preemption included), the frame counts per bus and the LiDAR's rays, packets and send failures.
//
// Failure: the constructor throws porter::LoadError for a bad scene, robot or payload file;
// a bus or LiDAR socket that cannot be opened, or an Embree failure, makes ok() false with
// error() naming it.
// Thread-safety: one thread builds and runs it.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "porter/can/can_bus.hpp"
#include "porter/lcm_bus.hpp"
#include "porter/livox_sim/realtime_sender.hpp"
#include "porter/sim/lidar_sensor.hpp"
#include "porter/sim/simulator.hpp"
#include "sim_config.hpp"

namespace porter::sim {

class SimProcess {
 public:
  SimProcess(const SimConfig& config, LcmBus& lcm);

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  Simulator& simulator() { return *sim_; }
  /// The simulated MID-360 and its sender (null / empty when the config disables it).
  const LidarSensor* lidar() const { return lidar_; }
  const livox::sim::RealtimeSender* lidar_sender() const {
    return lidar_sender_ ? &*lidar_sender_ : nullptr;
  }

  /// Runs until stop() returns true; returns 0.
  int run(const std::function<bool()>& stop);

  /// Simulated seconds per wall second over the whole run, and the fraction of wall time spent
  /// stepping (valid after run()).
  double real_time_factor() const { return rtf_; }
  double busy_fraction() const { return busy_; }
  /// Process CPU time (all threads) per wall second over the run.
  double cpu_fraction() const { return cpu_; }

 private:
  SimConfig config_;
  LcmBus& lcm_;
  std::vector<std::unique_ptr<can::CanBus>> endpoints_;
  std::unique_ptr<Simulator> sim_;
  std::optional<livox::sim::RealtimeSender> lidar_sender_;
  LidarSensor* lidar_ = nullptr;  // owned by sim_
  std::string error_;
  double rtf_ = 0.0;
  double busy_ = 0.0;
  double cpu_ = 0.0;
};

}  // namespace porter::sim
