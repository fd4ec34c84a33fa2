#pragma once
// A simulated sensor porter-sim hosts: the LiDAR (MID-360 packets over UDP), the LIO pose, the
// ground-truth publisher. The Simulator calls advance() after every step; the sensor reads the
// world and emits (sends, publishes or hands to a callback) whatever it produces with a time in
// the step's interval.
//
//   class MyLidar final : public porter::sim::SimSensor {
//     std::string name() const override { return "mid360"; }
//     void advance(const World& world, double t0_s, double t1_s) override {
//       if (world.obstacles_version() != built_version_) rebuild(world.obstacles());
//       for (each ray whose time t falls in (t0_s, t1_s]) {
//         const RobotSample robot = world.robot_at(t);   // pose and joints at the ray's time
//         ... cast against world.obstacles() and the robot's links and payload ...
//       }
//       ... send packets stamped world.utime_at(t) ...
//     }
//   };
//
// Contract:
// - Intervals are contiguous and increasing: each call's t0_s is the previous call's t1_s; the
//   first call's t0_s is the simulation's start time.
// - During the call, world.robot_at(t) is exact for t in [t0_s, t1_s] (interpolated between the
//   simulation's steps) and valid back to world.history_start_s(); world.obstacles() is the
//   obstacle set at t1_s.
// - advance() must not block: in real time it runs in the simulation's loop (1 kHz by default),
//   so a sensor with heavy work per interval (a 200 kHz ray caster) should keep it bounded.
// Thread-safety: called from the simulation thread only.

#include <string>

#include "porter/sim/world.hpp"

namespace porter::sim {

class SimSensor {
 public:
  virtual ~SimSensor() = default;
  virtual std::string name() const = 0;
  virtual void advance(const World& world, double t0_s, double t1_s) = 0;
};

}  // namespace porter::sim
