#pragma once
// A robot that follows a script: configurations at given times, interpolated linearly (yaw
// along the shorter arc) and held after the last one, or repeated when `loop` is set. Drives
// the standalone simulated MID-360 and the tests (a static robot is one waypoint).
//
// Thread-safety: immutable after construction; at() is reentrant.

#include <vector>

#include "porter/core/types.hpp"

namespace porter::livox::sim {

struct Waypoint {
  double t_s = 0.0;
  RobotConfiguration config;
};

class ScriptedMotion {
 public:
  /// `waypoints` must be non-empty with strictly increasing times (the loaders check this);
  /// an empty script holds the default configuration.
  explicit ScriptedMotion(std::vector<Waypoint> waypoints, bool loop = false);

  RobotConfiguration at(double t_s) const;
  double duration_s() const;

 private:
  std::vector<Waypoint> waypoints_;
  bool loop_;
};

}  // namespace porter::livox::sim
