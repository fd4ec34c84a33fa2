#pragma once
// A short history of the robot's configuration, sampled from the world and interpolated at
// any time inside it (the simulated LiDAR poses rays and links at each point's time and
// differentiates the sensor's motion for its IMU).
//
// Interpolation is linear in x, y and the joint angles and along the shorter arc in yaw;
// outside the sampled span the nearest sample is returned. Samples older than keep_s before the
// newest are dropped.
//
// Thread-safety: one thread.

#include <cstdint>
#include <deque>

#include "porter/core/types.hpp"

namespace porter::livox::sim {

class StateHistory {
 public:
  explicit StateHistory(double keep_s = 0.05) : keep_ns_(static_cast<std::int64_t>(keep_s * 1e9)) {}

  /// Adds a sample; a time not after the newest sample replaces nothing and is ignored.
  void add(std::int64_t t_ns, const RobotConfiguration& config);
  /// Configuration at t_ns (see above). A default configuration when empty.
  RobotConfiguration at(std::int64_t t_ns) const;

  bool empty() const { return samples_.empty(); }
  std::int64_t newest_ns() const { return samples_.empty() ? 0 : samples_.back().t_ns; }
  void clear() { samples_.clear(); }

 private:
  struct Sample {
    std::int64_t t_ns;
    RobotConfiguration config;
  };
  std::int64_t keep_ns_;
  std::deque<Sample> samples_;
};

/// The configuration a fraction `s` in [0, 1] of the way from `a` to `b` (yaw along the
/// shorter arc).
RobotConfiguration interpolate(const RobotConfiguration& a, const RobotConfiguration& b, double s);

}  // namespace porter::livox::sim
