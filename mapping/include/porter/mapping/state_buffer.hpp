#pragma once
// A short history of the robot's whole-body configuration (from ROBOT_STATE), interpolated at
// any time inside it: the mapper poses each LiDAR point with the state at that point's time
// (de-skewing the sweep of a moving robot) and poses the self-filter with the arm at it.
//
// Interpolation is linear in x, y and the joint angles and along the shorter arc in yaw.
// Outside the sampled span the nearest sample is held and at() says so.
//
// Time: µs on the clock of ROBOT_STATE.utime and point_cloud_t.utime (both wall-clock utime).
// Thread-safety: none; the mapper process guards its buffer with a mutex.

#include <cstdint>
#include <deque>

#include "porter/core/types.hpp"

namespace porter::mapping {

class StateBuffer {
 public:
  /// Samples older than keep_s before the newest are dropped.
  explicit StateBuffer(double keep_s = 2.0) : keep_us_(static_cast<std::int64_t>(keep_s * 1e6)) {}

  /// Adds a sample. A time not after the newest sample is ignored and counted in rejected().
  void add(std::int64_t t_us, const RobotConfiguration& config);

  /// Where at() found the time.
  enum class Lookup { inside, before_first, after_last, empty };
  /// Configuration at t_us (see above).
  Lookup at(std::int64_t t_us, RobotConfiguration& out) const;

  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }
  std::int64_t oldest_us() const { return samples_.empty() ? 0 : samples_.front().t_us; }
  std::int64_t newest_us() const { return samples_.empty() ? 0 : samples_.back().t_us; }
  std::uint64_t rejected() const { return rejected_; }
  void clear() { samples_.clear(); }

 private:
  struct Sample {
    std::int64_t t_us;
    RobotConfiguration config;
  };
  std::int64_t keep_us_;
  std::deque<Sample> samples_;
  std::uint64_t rejected_ = 0;
};

/// The configuration a fraction s in [0, 1] of the way from a to b (yaw along the shorter arc,
/// wrapped into (-pi, pi]).
RobotConfiguration interpolate_configuration(const RobotConfiguration& a, const RobotConfiguration& b,
                                             double s);

}  // namespace porter::mapping
