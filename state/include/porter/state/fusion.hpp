#pragma once
// State fusion of porter-state: wheel odometry (BASE_STATE), LiDAR-inertial poses (LIO_POSE,
// when present) and the arm's joints (ARM_STATE) into one whole-body state (ROBOT_STATE),
// stepped with explicit time so tests drive it without sleeping.
//
// Pose. The world pose of the base is T_W_B(t) = T_W_odom * T_odom_B(t): the odometry pose
// T_odom_B (drifting, never jumping) corrected by one planar transform T_W_odom.
//   - Without LIO, T_W_odom anchors the first odometry sample at params.start_pose
//     (pose_source POSE_WHEEL_ODOM).
//   - A LIO pose T_W_B(t_L) stamped t_L sets T_W_odom = T_W_B(t_L) * T_odom_B(t_L)^-1, with the
//     odometry at t_L interpolated from a short history. Until the next LIO pose the output is
//     the LIO pose propagated by the odometry increment since t_L, so the state is smooth at the
//     output rate (pose_source POSE_LIO while LIO is fresh). LIO is the truth: a pose that
//     disagrees with the propagated one by more than the jump limits is taken all the same, and
//     counted (and reported to the caller so it is logged).
//   - When LIO goes stale, the last correction stays and the pose continues on odometry
//     (pose_source POSE_WHEEL_ODOM).
//   - An odometry source that restarts (its pose steps by more than odom_reset_*, or its stamp
//     goes backwards) is re-anchored so the world pose continues from where it was.
//   - The output pose is extrapolated from the newest odometry sample to the output time with
//     its (v, omega), by at most max_extrapolation_s; its utime says which instant it is.
//
// Freshness. An input is fresh while now - (the time it was received) <= its timeout (the
// fusion's own clock, so a sender's clock offset does not matter). base_valid / arm_valid /
// pose_valid report freshness; the *_utime fields report the stamps used; the last values are
// kept while stale (flags false), and a returning input is used again at once.
//
// E-stop: estop_active = the latest ESTOP message's state OR a fresh base / arm reporting one.
//
// Time: every time is a utime (µs). Thread-safety: not thread-safe; one thread calls every
// member. Failure: nothing throws after construction (the constructor throws
// std::invalid_argument on invalid params); no member allocates once the odometry history has
// reached its length.

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "porter/core/types.hpp"

namespace porter::state {

enum class PoseSource : std::int8_t { none = 0, lio = 1, wheel_odom = 2 };

const char* to_string(PoseSource source);

struct FusionParams {
  BasePose start_pose;               ///< T_W_B at the first odometry sample when no LIO, m / rad
  bool use_lio = true;               ///< false: LIO poses are ignored
  double base_timeout_s = 0.1;       ///< BASE_STATE staleness limit, s
  double arm_timeout_s = 0.05;       ///< ARM_STATE staleness limit, s
  double lio_timeout_s = 0.3;        ///< LIO_POSE staleness limit, s
  double lio_jump_m = 0.2;           ///< LIO disagreement counted as a jump, m
  double lio_jump_rad = 0.1;         ///< ... or rad
  double odom_history_s = 1.0;       ///< odometry kept for LIO stamps in the past, s
  double odom_reset_m = 0.5;         ///< odometry step read as a source restart, m
  double odom_reset_rad = 0.5;       ///< ... or rad
  double max_extrapolation_s = 0.02; ///< output extrapolation from the newest odometry, s

  /// Throws std::invalid_argument naming the first invalid field.
  void validate() const;
};

struct OdometrySample {
  std::int64_t utime = 0;
  BasePose T_odom_B;          ///< odometry pose
  double v_mps = 0.0;         ///< forward speed of B, m/s
  double omega_radps = 0.0;   ///< yaw rate, rad/s
  bool estop_active = false;  ///< the base driver holds the base because of an e-stop
};

struct LioSample {
  std::int64_t utime = 0;     ///< the instant the pose refers to
  BasePose T_W_B;
};

struct ArmSample {
  std::int64_t utime = 0;
  JointVector q_rad = JointVector::Zero();
  JointVector qd_radps = JointVector::Zero();
  bool estop_active = false;
};

/// What an odometry sample did (for the process's log).
struct OdometryUpdate {
  bool first = false;       ///< the first sample: the pose is anchored
  bool reset = false;       ///< a source restart was detected and re-anchored
  bool out_of_order = false;  ///< older than the previous sample: ignored
};

/// What a LIO pose did.
struct LioUpdate {
  bool used = false;
  bool jumped = false;         ///< disagreed with the propagated pose beyond the jump limits
  double jump_m = 0.0;         ///< position disagreement, m
  double jump_rad = 0.0;       ///< heading disagreement, rad
  bool outside_history = false;  ///< its stamp was outside the odometry history (nearest end used)
  std::string ignored_reason;  ///< why it was not used ("" when used)
};

struct FusedState {
  std::int64_t utime = 0;       ///< instant the pose refers to
  BasePose T_W_B;
  double v_mps = 0.0;
  double omega_radps = 0.0;
  PoseSource pose_source = PoseSource::none;
  bool base_valid = false;
  bool arm_valid = false;
  bool pose_valid = false;
  std::int64_t base_utime = 0;  ///< stamp of the odometry used (0 = none yet)
  std::int64_t arm_utime = 0;
  std::int64_t pose_utime = 0;  ///< stamp of the LIO pose (POSE_LIO) or odometry used
  bool has_arm = false;         ///< an arm sample was ever received
  JointVector q_rad = JointVector::Zero();
  JointVector qd_radps = JointVector::Zero();
  bool estop_active = false;
};

struct FusionCounters {
  std::uint64_t odometry = 0;
  std::uint64_t odometry_resets = 0;
  std::uint64_t odometry_out_of_order = 0;
  std::uint64_t lio = 0;
  std::uint64_t lio_jumps = 0;
  std::uint64_t lio_ignored = 0;
  std::uint64_t arm = 0;
};

class StateFusion {
 public:
  explicit StateFusion(FusionParams params);

  const FusionParams& params() const { return params_; }

  OdometryUpdate on_odometry(const OdometrySample& sample, std::int64_t receive_utime);
  LioUpdate on_lio(const LioSample& sample, std::int64_t receive_utime);
  void on_arm(const ArmSample& sample, std::int64_t receive_utime);
  void on_estop(bool active);

  /// The fused state at now_utime.
  FusedState output(std::int64_t now_utime) const;

  const FusionCounters& counters() const { return counters_; }
  /// The current correction T_W_odom.
  const BasePose& T_W_odom() const { return T_W_odom_; }

 private:
  struct Stamped {
    std::int64_t utime;
    BasePose T_odom_B;
  };
  // Odometry pose at `utime` from the history; *outside when clamped to an end.
  BasePose odom_at(std::int64_t utime, bool* outside) const;

  FusionParams params_;
  std::deque<Stamped> history_;
  std::optional<OdometrySample> odom_;
  std::int64_t odom_receive_utime_ = 0;
  BasePose T_W_odom_;
  std::optional<LioSample> lio_;
  std::int64_t lio_receive_utime_ = 0;
  std::optional<ArmSample> arm_;
  std::int64_t arm_receive_utime_ = 0;
  bool estop_ = false;
  FusionCounters counters_;
};

}  // namespace porter::state
