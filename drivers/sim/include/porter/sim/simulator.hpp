#pragma once
// The simulation as a library: simulated devices on named CAN buses, the world, the ground-truth
// sources and the sensors, stepped on simulated time. porter-sim drives it in real time; tests
// and benchmarks call step_to() as fast as they like.
//
//   Simulator sim(std::move(world));
//   sim.add_bus("base", base_endpoint.get());                  // an open CanBus, or nullptr
//   auto* fw = sim.add_node("base", std::make_unique<ScoutMiniFirmware>(...));
//   sim.set_base_source(...); sim.set_joint_source(...);
//   sim.add_sensor(std::make_unique<LioPoseSensor>(...));
//   for (;;) sim.step_to(now_s);
//
// One step_to(t) call:
//   1. every frame waiting on each bus endpoint (CanBus::receive with timeout 0) is handed to
//      that bus's devices at the current time (nothing crosses a dropped bus);
//   2. then, in steps of at most step_s up to t: every device advances; the frames it sends go
//      to the other devices on its bus and, stamped with wall-clock utime (World::utime_at), to
//      the bus endpoint; the ground truth is read from the sources and recorded in the world;
//      every sensor advances over the step's interval.
// In real time the loop calls step_to() every step_s, so a frame waits at most one step (1 ms
// by default) to reach a device.
//
// Faults on demand go through apply(SimCommand) or the named calls; each returns a SimResult
// saying what happened or why it was refused. Devices are addressed by SimulatedNode::name().
//
// Failure: nothing throws during stepping; a send failure on an endpoint is counted per bus.
// Thread-safety: none; one thread steps the simulator (porter-sim's main loop).

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "porter/can/can_bus.hpp"
#include "porter/can/simulated_node.hpp"
#include "porter/sim/sensor.hpp"
#include "porter/sim/sim_command.hpp"
#include "porter/sim/truth_sources.hpp"
#include "porter/sim/world.hpp"

namespace porter::sim {

struct SimParams {
  double step_s = 0.001;  ///< largest simulation step (devices, truth, sensors)
};

struct BusStats {
  std::uint64_t frames_in = 0;       ///< frames read from the endpoint
  std::uint64_t frames_out = 0;      ///< frames sent to the endpoint
  std::uint64_t frames_dropped = 0;  ///< frames lost to a dropped bus
  std::uint64_t send_failures = 0;   ///< endpoint send() that did not return ok
};

class Simulator {
 public:
  explicit Simulator(World world, SimParams params = {});

  World& world() { return world_; }
  const World& world() const { return world_; }
  double time_s() const { return t_s_; }

  /// Declares a bus; `endpoint` (may be null: devices talk only among themselves and to the
  /// tap) must outlive the simulator. False when the name is in use.
  bool add_bus(const std::string& name, can::CanBus* endpoint);
  /// Hosts a device on a bus. Returns the device, or nullptr when the bus is unknown or a
  /// device of that name exists.
  can::SimulatedNode* add_node(const std::string& bus, std::unique_ptr<can::SimulatedNode> node);
  can::SimulatedNode* node(const std::string& device) const;
  std::vector<std::string> bus_names() const;
  const BusStats* bus_stats(const std::string& bus) const;

  void set_base_source(std::unique_ptr<BaseSource> source) { base_source_ = std::move(source); }
  void set_joint_source(std::unique_ptr<JointSource> source) { joint_source_ = std::move(source); }
  void add_sensor(std::unique_ptr<SimSensor> sensor) { sensors_.push_back(std::move(sensor)); }

  /// Called with every frame on every bus: from_device = true for frames a device sent, false
  /// for frames that came in through the endpoint or inject(). For tests and recording.
  using FrameTap =
      std::function<void(const std::string& bus, const can::CanFrame& frame, bool from_device)>;
  void set_frame_tap(FrameTap tap) { tap_ = std::move(tap); }

  /// Hands a frame to the devices of `bus` at the current time, as if it came from the bus.
  bool inject(const std::string& bus, const can::CanFrame& frame);

  /// Advances the simulation to t_s (no-op when t_s is not later than time_s()).
  void step_to(double t_s);

  // ---- faults on demand ----------------------------------------------------------------------
  SimResult apply(const SimCommand& command);
  SimResult drop_bus(const std::string& bus, bool dropped);
  SimResult set_stream(const std::string& device, std::uint32_t can_id, bool enabled);
  SimResult raise_error(const std::string& device, std::uint32_t code);
  SimResult clear_errors(const std::string& device);
  SimResult power_cycle(const std::string& device, double off_s);

 private:
  struct Bus {
    std::string name;
    can::CanBus* endpoint = nullptr;
    bool dropped = false;
    std::vector<std::unique_ptr<can::SimulatedNode>> nodes;
    BusStats stats;
  };

  Bus* find_bus(const std::string& name);
  void deliver_inbound();
  void substep(double t_s);
  void record_truth(double t_s);

  World world_;
  SimParams params_;
  double t_s_ = 0.0;
  std::deque<Bus> buses_;  // deque: Bus addresses stay valid as buses are added
  std::unique_ptr<BaseSource> base_source_;
  std::unique_ptr<JointSource> joint_source_;
  std::vector<std::unique_ptr<SimSensor>> sensors_;
  FrameTap tap_;
  std::vector<can::CanFrame> scratch_;
};

}  // namespace porter::sim
