#pragma once
// The simulated Livox MID-360 as a sensor of the simulated world (sensor.hpp): the ray caster and
// packet encoder of porter::livox::sim::SimulatedMid360, fed with the world's ground truth.
//
//   sim.add_sensor(std::make_unique<LidarSensor>(params, sim.world(),
//       [&](const std::vector<livox::sim::SimPacket>& p) { sender.send(p); }));
//
// Each advance(world, t0, t1) casts every ray whose time lies in (t0, t1] and hands the packets
// sent in that interval to the sink, in time order:
// - rays start from the sensor's pose (mount params.T_B_S on the base) at the ray's own time,
//   read from world.robot_at(t) (the simulation's ground truth, interpolated between steps);
// - they hit the world's obstacles (the scene's and those added or removed at run time: the
//   ray-casting scene is rebuilt whenever world.obstacles_version() changes), the ground, and
//   the robot's own links and payload posed at the configuration of the moment (the joint
//   angles the arm firmware reports, so the moving arm and payload are seen where they are).
// Work per call is bounded by the interval: point_rate_hz x (t1 - t0) rays (200 per 1 ms step at
// the MID-360's rate) plus, after a world change, one rebuild of the obstacle scene.
//
// Time stamps: for time_type no_sync the packets carry the sensor's time since power-on (the
// simulation's start), as the unsynchronised device does; for ptp / gps, the world's wall-clock
// time (World::utime_at), read at the first advance().
//
// Failure: ok() is false when Embree could not build a scene (error() says why); the sensor then
// sends packets without returns. Nothing throws after construction.
// Thread-safety: simulation thread only.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "porter/livox_sim/simulated_mid360.hpp"
#include "porter/sim/sensor.hpp"

namespace porter::sim {

class LidarSensor final : public SimSensor {
 public:
  using PacketSink = std::function<void(const std::vector<livox::sim::SimPacket>&)>;

  /// `world` gives the robot (payload attached) and the obstacles at construction; the sensor
  /// reads the world passed to advance() afterwards.
  LidarSensor(const livox::sim::Mid360SimParams& params, const World& world, PacketSink sink);

  std::string name() const override { return "mid360"; }
  void advance(const World& world, double t0_s, double t1_s) override;

  bool ok() const { return lidar_->ok(); }
  const std::string& error() const { return lidar_->error(); }
  const livox::sim::SimulatedMid360& lidar() const { return *lidar_; }
  const livox::sim::SimStats& stats() const { return lidar_->stats(); }
  /// Rebuilds of the obstacle scene after world changes, and the time the last one took, s.
  std::uint64_t rebuilds() const { return rebuilds_; }
  double last_rebuild_s() const { return last_rebuild_s_; }
  /// CPU time of the calling thread spent in advance() (ray casting, packets, the sink), s.
  double cpu_s() const { return cpu_s_; }

 private:
  const World* world_;
  std::unique_ptr<livox::sim::SimulatedMid360> lidar_;
  PacketSink sink_;
  std::vector<livox::sim::SimPacket> packets_;
  std::uint64_t obstacles_version_;
  bool started_ = false;
  std::uint64_t rebuilds_ = 0;
  double last_rebuild_s_ = 0.0;
  double cpu_s_ = 0.0;
};

}  // namespace porter::sim
