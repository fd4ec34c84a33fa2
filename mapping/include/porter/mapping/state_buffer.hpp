#pragma once
// A short history of the robot's whole-body configuration (from ROBOT_STATE), interpolated at
// any time inside it: the mapper poses each LiDAR point with the state at that point's time
// (de-skewing the sweep of a moving robot) and poses the self-filter with the arm at it.
//
// Two tracks, each on its own stamps: the base pose (ROBOT_STATE.utime, the instant of the
// odometry / LIO pose) and the arm's joint angles (ROBOT_STATE.arm_utime, the instant of the
// ARM_STATE sample porter-state passed on). porter-state publishes the newest arm sample with
// every state at 100 Hz, so the joint angles of a ROBOT_STATE are older than its utime by the
// arm's own latency; pairing them with utime would pose the arm late (docs/mapping.md,
// "Self-filter on a moving robot"). A configuration at time t is the base interpolated at t and
// the arm interpolated at t, each from its own samples.
//
// Interpolation is linear in x, y and the joint angles and along the shorter arc in yaw.
// Outside a track's sampled span its nearest sample is held and at() says so.
//
// Time: µs on the clock of ROBOT_STATE.utime and point_cloud_t.utime (both wall-clock utime).
// Thread-safety: none; the mapper process guards its buffer with a mutex.

#include <cstdint>
#include <deque>

#include "porter/core/types.hpp"

namespace porter::mapping {

class StateBuffer {
 public:
  /// Samples older than keep_s before the newest (per track) are dropped.
  explicit StateBuffer(double keep_s = 2.0) : keep_us_(static_cast<std::int64_t>(keep_s * 1e6)) {}

  /// Adds a base and an arm sample of the same instant (a simulator's ground truth, tests).
  void add(std::int64_t t_us, const RobotConfiguration& config);
  /// Adds a base pose sample. A time not after the newest base sample is ignored and counted
  /// in rejected().
  void add_base(std::int64_t t_us, const BasePose& base);
  /// Adds an arm sample stamped with its own time. A stamp not after the newest arm sample is
  /// ignored (porter-state repeats an arm sample until the next arrives): returns false.
  /// `arrived_us` is the base time (ROBOT_STATE.utime) of the state that brought the sample; the
  /// two-argument form takes the sample's own time.
  bool add_arm(std::int64_t t_us, const JointVector& q_rad, std::int64_t arrived_us);
  bool add_arm(std::int64_t t_us, const JointVector& q_rad) { return add_arm(t_us, q_rad, t_us); }

  /// Where at() found the time (the worse of the two tracks: empty, then before/after, then
  /// inside).
  enum class Lookup { inside, before_first, after_last, empty };
  /// Configuration at t_us (see above). An empty arm track gives q = 0 and Lookup::empty.
  Lookup at(std::int64_t t_us, RobotConfiguration& out) const;

  /// True when both tracks hold samples at or before t0_us and at or after t1_us: every time
  /// in [t0_us, t1_us] is interpolated, nothing held.
  bool covers(std::int64_t t0_us, std::int64_t t1_us) const;

  /// Whether the samples that came with states up to base time `deadline_us` cover
  /// [t0_us, t1_us] (both tracks hold samples at or before t0_us; the first base sample at or
  /// after t1_us is not later than the deadline; the first arm sample at or after t1_us came
  /// with a state not later than the deadline):
  ///   yes      covered;
  ///   never    cannot be: a track begins after t0_us, or the states have passed the deadline
  ///            (or brought the sample that would cover t1_us only after it);
  ///   not_yet  the base track has not reached the deadline yet.
  /// The answer depends on the states received (in their order) only, not on when it is asked:
  /// not_yet can turn into yes or never as states come, and yes or never stays so (as long as
  /// the samples needed are still kept: keep_s).
  enum class Cover { yes, not_yet, never };
  Cover covers_by(std::int64_t t0_us, std::int64_t t1_us, std::int64_t deadline_us) const;

  bool empty() const { return base_.empty() && arm_.empty(); }
  std::size_t base_size() const { return base_.size(); }
  std::size_t arm_size() const { return arm_.size(); }
  /// The span both tracks cover: [max of the oldest, min of the newest]; 0 when a track is empty.
  std::int64_t oldest_us() const;
  std::int64_t newest_us() const;
  std::int64_t newest_base_us() const { return base_.empty() ? 0 : base_.back().t_us; }
  std::int64_t newest_arm_us() const { return arm_.empty() ? 0 : arm_.back().t_us; }
  std::uint64_t rejected() const { return rejected_; }
  void clear() {
    base_.clear();
    arm_.clear();
  }

 private:
  struct BaseSample {
    std::int64_t t_us;
    BasePose base;
  };
  struct ArmSample {
    std::int64_t t_us;
    JointVector q_rad;
    std::int64_t arrived_us;  ///< base time of the state that brought it
  };
  std::int64_t keep_us_;
  std::deque<BaseSample> base_;
  std::deque<ArmSample> arm_;
  std::uint64_t rejected_ = 0;
};

/// The configuration a fraction s in [0, 1] of the way from a to b (yaw along the shorter arc,
/// wrapped into (-pi, pi]).
RobotConfiguration interpolate_configuration(const RobotConfiguration& a, const RobotConfiguration& b,
                                             double s);

}  // namespace porter::mapping
