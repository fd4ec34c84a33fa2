#pragma once
// The loop logic of porter-tracker, stepped with explicit time: which trajectory is tracked,
// when commands are zero (stale inputs, e-stop, faults), the hold at the end and the hand-off
// between trajectories. The process (tracker/app/) feeds it decoded messages and calls step()
// from its 100 Hz loop; tests drive it with made-up times, without sleeping.
//
// Time: every time is a utime (µs, the clock of the messages' utime fields; the process passes
// its wall clock). Staleness is judged on the tracker's own clock: the age of an input is
// now - (the time it was received), so a sender's clock offset does not matter; only the
// trajectory's start_utime (the hand-off time chosen by the planner) is read on the sender's
// clock.
//
// States (tracker_status_t.STATE_*), checked in this order at every step:
//   ESTOP            an ESTOP (active = true) was received and no release (active = false) since,
//                    or the latest ROBOT_STATE reports an engaged e-stop. Zero commands
//                    (enabled = false). A release drops the trajectory (the reference moved on
//                    while stopped) and trajectories offered while the e-stop is latched are
//                    refused, so the tracker waits, IDLE, for a new one.
//   IDLE             no trajectory. Zero commands.
//   STALE_STATE      no ROBOT_STATE within state_timeout_s, or the latest lacks a fresh pose or
//                    base (or arm, when require_arm_state) or has the wrong joint count. Zero.
//   STALE_TRAJECTORY trajectory_timeout_s > 0 and no TRAJECTORY for that long. Zero.
//   FAULT            the position or heading error exceeded its limit; zero until a new
//                    trajectory is accepted.
//   FINISHED         past the end: base enabled with zero velocity, arm holding the final joint
//                    angles with zero velocity.
//   TRACKING         base: control law (control_law.hpp) on the trajectory's sample; arm: joint
//                    angles and feed-forward velocities of the sample.
//
// Trajectories: on_trajectory() refuses (with a reason) a frame other than params.frame_id, a
// message older than trajectory_max_age_s on arrival, a start more than max_start_lag_s in the
// past, and anything while the e-stop is latched. An accepted trajectory is pending until its
// start_utime (the hand-off time), then replaces the active one, sampled at now - start_utime;
// a later offer replaces an earlier pending one. A trajectory continuous with the active one at
// the hand-off gives a command without a jump (the acceleration limit bounds the change of the
// command in every case).
//
// Thread-safety: not thread-safe; one thread calls every member. Failure: nothing throws after
// construction (the constructor throws std::invalid_argument on invalid params); step() never
// allocates except when a state change composes its message.

#include <cstdint>
#include <optional>
#include <string>

#include "porter/core/robot_model.hpp"
#include "porter/core/trajectory.hpp"
#include "porter/core/types.hpp"
#include "porter/tracker/control_law.hpp"

namespace porter::tracker {

enum class TrackerState : std::int8_t {
  idle = 0,
  tracking = 1,
  finished = 2,
  stale_state = 3,
  stale_trajectory = 4,
  estop = 5,
  fault = 6,
};

/// "IDLE", "TRACKING", ...
const char* to_string(TrackerState state);

struct TrackerParams {
  TrackingGains gains;
  BaseLimits base_limits;                         ///< wheel radius, track, wheel speed/accel limits
  JointVector joint_velocity_max_radps = JointVector::Constant(1e9);  ///< feed-forward clamp
  std::string frame_id = "world";                 ///< frame trajectories must be in
  double period_s = 0.01;                         ///< nominal control period (first step's dt)
  double state_timeout_s = 0.1;                   ///< ROBOT_STATE older than this is stale
  bool require_arm_state = true;                  ///< a stale arm in ROBOT_STATE stops tracking
  double trajectory_timeout_s = 0.0;              ///< 0 = a trajectory never goes stale
  double trajectory_max_age_s = 1.0;              ///< refuse a TRAJECTORY this old on arrival
  double max_start_lag_s = 0.2;                   ///< refuse a start further in the past
  double max_position_error_m = 0.5;              ///< FAULT beyond this position error
  double max_yaw_error_rad = 0.6;                 ///< FAULT beyond this heading error

  /// Throws std::invalid_argument naming the first invalid field.
  void validate() const;
};

/// The fused state as the tracker uses it (from ROBOT_STATE).
struct MeasuredState {
  std::int64_t utime = 0;
  BasePose pose;
  double v_mps = 0.0;
  double omega_radps = 0.0;
  bool pose_valid = false;
  bool base_valid = false;
  bool arm_valid = false;
  int num_joints = 0;
  JointVector q_rad = JointVector::Zero();
  JointVector qd_radps = JointVector::Zero();
  bool estop_active = false;
};

/// A trajectory offered for tracking (from TRAJECTORY).
struct TrajectoryOffer {
  Trajectory trajectory;
  std::int64_t utime = 0;        ///< publish time, µs
  std::int64_t start_utime = 0;  ///< t = 0 of the trajectory, µs
  std::int64_t plan_id = 0;
  std::string frame_id;
};

struct OfferResult {
  bool accepted = false;
  std::string reason;  ///< why it was refused ("" when accepted)
};

/// What one step commands and reports.
struct TrackerOutput {
  std::int64_t utime = 0;
  TrackerState state = TrackerState::idle;
  bool state_changed = false;   ///< state differs from the previous step's
  std::string message;          ///< cause of the current non-TRACKING state ("" when tracking)
  std::int64_t plan_id = -1;    ///< trajectory being tracked, -1 when none

  bool base_enabled = false;
  BaseCommand base;             ///< zero unless enabled
  bool base_speed_limited = false;
  bool base_accel_limited = false;

  bool arm_enabled = false;
  JointVector q_rad = JointVector::Zero();
  JointVector qd_radps = JointVector::Zero();

  double t_s = 0.0;             ///< time into the trajectory, s
  double duration_s = 0.0;
  PoseError error_reference_frame;  ///< along / cross / yaw (reference minus measured)
  JointVector q_error_rad = JointVector::Zero();
};

class Tracker {
 public:
  explicit Tracker(TrackerParams params);

  const TrackerParams& params() const { return params_; }

  void on_state(const MeasuredState& state, std::int64_t receive_utime);
  OfferResult on_trajectory(TrajectoryOffer offer, std::int64_t receive_utime);
  /// Records a TRAJECTORY that could not be decoded or converted (bad dimension, order, ...), so
  /// the status says why it was ignored.
  void on_invalid_trajectory(std::int64_t plan_id, const std::string& reason);
  /// ESTOP message: active = true latches, active = false releases.
  void on_estop(bool active, const std::string& reason, std::int64_t receive_utime);

  /// Computes this period's commands. Call at the control rate with the current time.
  const TrackerOutput& step(std::int64_t now_utime);

  const TrackerOutput& output() const { return out_; }
  bool estop_latched() const { return estop_latched_; }
  bool has_trajectory() const { return active_.has_value(); }
  bool has_pending() const { return pending_.has_value(); }
  /// The last refusal ("" when none), e.g. for TRACKER_STATUS while tracking on.
  const std::string& last_refusal() const { return last_refusal_; }
  std::uint64_t refused_count() const { return refused_; }

 private:
  struct Active {
    TrajectoryOffer offer;
    std::int64_t receive_utime = 0;
  };

  void set_state(TrackerState state, std::string message);
  void command_zero();
  // Returns the cause when the state is stale, "" when usable.
  std::string state_problem(std::int64_t now_utime) const;

  TrackerParams params_;
  std::optional<MeasuredState> state_;
  std::int64_t state_receive_utime_ = 0;
  std::optional<Active> active_;
  std::optional<Active> pending_;
  std::int64_t last_trajectory_receive_utime_ = 0;
  bool estop_latched_ = false;
  std::string estop_reason_;
  bool fault_ = false;
  std::string fault_message_;
  std::string last_refusal_;
  std::uint64_t refused_ = 0;
  std::string release_note_;
  TrackerOutput out_;
  TrackerState previous_state_ = TrackerState::idle;
  bool stepped_ = false;
  std::int64_t last_step_utime_ = 0;
  BaseCommand last_command_;
};

}  // namespace porter::tracker
